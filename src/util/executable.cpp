#include "util/executable.h"

namespace pluvia {

const std::filesystem::path& executablePath() {
  static const std::filesystem::path path = [] {
    std::error_code ec;
    std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::filesystem::path() : exe;
  }();
  return path;
}

}  // namespace pluvia
