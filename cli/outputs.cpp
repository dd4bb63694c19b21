#include "outputs.h"

#include <filesystem>

#include "image/image_io.h"

namespace epsray {

namespace fs = std::filesystem;

output_files::~output_files() {
  if (!kept_) roll_back();
}

void output_files::made_folder(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) folder_ = dir;
}

void output_files::wrote(const std::string& path) {
  std::error_code ec;
  if (!written_in_place(path) && fs::is_regular_file(fs::symlink_status(path, ec))) files_.push_back(path);
}

void output_files::roll_back() {
  std::error_code ec;
  for (auto it = files_.rbegin(); it != files_.rend(); ++it) fs::remove(*it, ec);
  files_.clear();
  if (!folder_.empty() && fs::is_empty(folder_, ec)) fs::remove(folder_, ec);
  folder_.clear();
}

}  // namespace epsray
