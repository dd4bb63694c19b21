// The files one command has put in place, removed again when the command fails after
// writing some of them (a full disk at the stats file): a run leaves all its outputs
// or none of them.
#pragma once
#include <string>
#include <vector>

namespace epsray {

class output_files {
 public:
  output_files() = default;
  output_files(const output_files&) = delete;
  output_files& operator=(const output_files&) = delete;
  // Unless kept, everything recorded is removed: an exception is on its way out.
  ~output_files();

  // A folder this command is about to make (walk's --out-dir): removed on failure if it
  // did not exist before and is empty by then.
  void made_folder(const std::string& dir);
  // A file just written whole. Only a plain regular file is recorded: a device, a FIFO,
  // /dev/stdout or a symbolic link given as an output is never removed.
  void wrote(const std::string& path);
  // Success (or an interrupt that keeps the frames done): nothing is removed.
  void keep() { kept_ = true; }
  // Removes every file recorded, newest first, and the folder made.
  void roll_back();

 private:
  std::vector<std::string> files_;
  std::string folder_;
  bool kept_ = false;
};

}  // namespace epsray
