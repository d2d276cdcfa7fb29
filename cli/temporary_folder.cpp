#include "temporary_folder.h"

#include <unistd.h>

#include <atomic>

#include <fmt/format.h>

namespace pluvia::cli {

TemporaryFolder::TemporaryFolder(const std::string& prefix) {
  static std::atomic<int> serial = 0;
  path_ = std::filesystem::temp_directory_path() /
          fmt::format("{}-{}-{}", prefix, ::getpid(), serial++);
  std::filesystem::create_directories(path_);
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace pluvia::cli
