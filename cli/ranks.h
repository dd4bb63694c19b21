// The ranks of a job started by mpirun (docs/mpi.md), over MPI where epsray was built with
// it. Everything MPI goes through here: this file's .cpp is the only one that includes
// mpi.h. A process not started by mpirun never initialises MPI and is rank 0 of 1.
#pragma once
#include <string>
#include <vector>

namespace epsray {

struct rank_info {
  bool mpi = false;  // MPI is initialised: the process was started by mpirun
  int rank = 0, size = 1;
  int local_rank = 0;  // among the ranks on this machine (Open MPI's OMPI_COMM_WORLD_LOCAL_RANK)
  std::string host;
};

// Initialises MPI when the process was started by mpirun (Open MPI's or PMIx's variables
// are set) and epsray has MPI; finalises it when destroyed. One in main, before anything
// else.
class rank_session {
 public:
  rank_session(int* argc, char*** argv);
  ~rank_session();
  rank_session(const rank_session&) = delete;
  rank_session& operator=(const rank_session&) = delete;
};

const rank_info& ranks();
// Whether what this rank writes to stderr reaches a terminal: a rank's stderr is a pipe to
// mpirun, so on Linux it is mpirun's own stderr that is looked at (the parent's, where
// mpirun started the rank on its own machine).
bool stderr_reaches_terminal();
// "Open MPI v4.1.4, ..." (the library's own words), or "none" without MPI.
std::string mpi_library();
// Finalises MPI and ends the process at once with `code`, without destructors: a walk
// that abandons the frame in hand while a thread is still rendering it (docs/mpi.md).
[[noreturn]] void finish_now(int code);

// The collectives the walk uses; with one rank each is the identity. Every rank calls
// them in the same order.
struct job_verdict {
  int code = 0;  // the largest of the ranks' codes
  int rank = 0;  // the first rank that gave it
};
job_verdict agree(int code);
int broadcast_from_root(int value);
void barrier();
// Rank 0 gets every rank's bytes, in rank order; the others get nothing.
std::vector<std::string> gather_to_root(const std::string& mine);
// Every rank gets every rank's string (the hosts), in rank order.
std::vector<std::string> gather_to_all(const std::string& mine);

// Small messages: an int to one rank, sent without blocking (completed before MPI is
// finalised), and received by polling.
void post(int to, int tag, int value);
// A message with `tag` from any rank, if one is waiting: true, with its sender and value.
bool poll(int tag, int& from, int& value);
// Waits for the message with `tag` from rank `from`.
int wait_for(int from, int tag);

}  // namespace epsray
