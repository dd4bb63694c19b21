#include "ranks.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <deque>

#ifdef EPSRAY_HAVE_MPI
#include <mpi.h>
#endif

namespace epsray {

namespace {

rank_info info;

// What mpirun tells the processes it starts (Open MPI; PMIx launchers such as srun's).
bool started_by_mpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK"); }

#ifdef EPSRAY_HAVE_MPI
// The sends not known to be complete, with the values they send (a deque never moves them).
struct pending_send {
  int value = 0;
  MPI_Request request = MPI_REQUEST_NULL;
};
std::deque<pending_send> sends;

void complete_sends() {
  for (pending_send& s : sends) MPI_Wait(&s.request, MPI_STATUS_IGNORE);
  sends.clear();
}

void finalize() {
  if (!info.mpi) return;
  complete_sends();
  int done = 0;
  MPI_Finalized(&done);
  if (!done) MPI_Finalize();
  info.mpi = false;
}
#else
int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : fallback;
}
#endif

}  // namespace

rank_session::rank_session(int* argc, char*** argv) {
  if (!started_by_mpirun()) return;
#ifdef EPSRAY_HAVE_MPI
  // Only the main thread calls MPI; rendering threads never do.
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  info.mpi = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &info.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &info.size);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, info.rank, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &info.local_rank);
  MPI_Comm_free(&node);
  char name[MPI_MAX_PROCESSOR_NAME] = {};
  int len = 0;
  MPI_Get_processor_name(name, &len);
  info.host.assign(name, size_t(len));
#else
  // Without MPI the process cannot reach its peers; main refuses to run when it has some.
  info.rank = env_int("OMPI_COMM_WORLD_RANK", env_int("PMIX_RANK", 0));
  info.size = env_int("OMPI_COMM_WORLD_SIZE", 1);
  info.local_rank = env_int("OMPI_COMM_WORLD_LOCAL_RANK", 0);
#endif
}

rank_session::~rank_session() {
#ifdef EPSRAY_HAVE_MPI
  finalize();
#endif
}

const rank_info& ranks() { return info; }

std::string mpi_library() {
#ifdef EPSRAY_HAVE_MPI
  char text[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  int len = 0;
  MPI_Get_library_version(text, &len);
  std::string s(text, size_t(len));
  const size_t end = s.find_first_of(",\n");  // "Open MPI v4.1.4, package: ..."
  return s.substr(0, end);
#else
  return "none";
#endif
}

bool stderr_reaches_terminal() {
  if (::isatty(STDERR_FILENO)) return true;
  if (!info.mpi) return false;
  char target[256] = {};
  const std::string fd = "/proc/" + std::to_string(::getppid()) + "/fd/2";
  const ssize_t n = ::readlink(fd.c_str(), target, sizeof target - 1);
  const std::string t(target, n > 0 ? size_t(n) : 0);
  return t.rfind("/dev/pts/", 0) == 0 || t.rfind("/dev/tty", 0) == 0;
}

void finish_now(int code) {
  std::fflush(stdout);
  std::fflush(stderr);
#ifdef EPSRAY_HAVE_MPI
  finalize();
#endif
  ::_exit(code);
}

job_verdict agree(int code) {
  job_verdict v{code, info.rank};
#ifdef EPSRAY_HAVE_MPI
  if (info.mpi) {
    struct {
      int value, rank;
    } in{code, info.rank}, out{};
    // MPI_MAXLOC: the largest code, and of the ranks with it the lowest.
    MPI_Allreduce(&in, &out, 1, MPI_2INT, MPI_MAXLOC, MPI_COMM_WORLD);
    v = {out.value, out.rank};
  }
#endif
  return v;
}

int broadcast_from_root(int value) {
#ifdef EPSRAY_HAVE_MPI
  if (info.mpi) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
  return value;
}

void barrier() {
#ifdef EPSRAY_HAVE_MPI
  if (info.mpi) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

std::vector<std::string> gather_to_root(const std::string& mine) {
#ifdef EPSRAY_HAVE_MPI
  if (info.mpi) {
    int size = int(mine.size());
    std::vector<int> sizes(size_t(info.size)), offsets(size_t(info.size));
    MPI_Gather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    int total = 0;
    for (int r = 0; r < info.size; ++r) offsets[size_t(r)] = total, total += sizes[size_t(r)];
    std::string all(size_t(info.rank == 0 ? total : 0), '\0');
    MPI_Gatherv(mine.data(), size, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    if (info.rank == 0)
      for (int r = 0; r < info.size; ++r) out.push_back(all.substr(size_t(offsets[size_t(r)]), size_t(sizes[size_t(r)])));
    return out;
  }
#endif
  return {mine};
}

std::vector<std::string> gather_to_all(const std::string& mine) {
#ifdef EPSRAY_HAVE_MPI
  if (info.mpi) {
    int size = int(mine.size());
    std::vector<int> sizes(size_t(info.size)), offsets(size_t(info.size));
    MPI_Allgather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
    int total = 0;
    for (int r = 0; r < info.size; ++r) offsets[size_t(r)] = total, total += sizes[size_t(r)];
    std::string all(size_t(total), '\0');
    MPI_Allgatherv(mine.data(), size, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
    std::vector<std::string> out;
    for (int r = 0; r < info.size; ++r) out.push_back(all.substr(size_t(offsets[size_t(r)]), size_t(sizes[size_t(r)])));
    return out;
  }
#endif
  return {mine};
}

void post(int to, int tag, int value) {
#ifdef EPSRAY_HAVE_MPI
  if (!info.mpi) return;
  pending_send& s = sends.emplace_back();
  s.value = value;
  MPI_Isend(&s.value, 1, MPI_INT, to, tag, MPI_COMM_WORLD, &s.request);
  // Completed ones are let go from the front, so the list stays short.
  while (!sends.empty()) {
    int done = 0;
    MPI_Test(&sends.front().request, &done, MPI_STATUS_IGNORE);
    if (!done) break;
    sends.pop_front();
  }
#endif
}

bool poll(int tag, int& from, int& value) {
#ifdef EPSRAY_HAVE_MPI
  if (!info.mpi) return false;
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  MPI_Recv(&value, 1, MPI_INT, st.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  from = st.MPI_SOURCE;
  return true;
#else
  return false;
#endif
}

int wait_for(int from, int tag) {
  int value = 0;
#ifdef EPSRAY_HAVE_MPI
  if (info.mpi) MPI_Recv(&value, 1, MPI_INT, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
#endif
  return value;
}

}  // namespace epsray
