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

std::vector<std::filesystem::path> shippedDataFolders(const std::filesystem::path& first,
                                                      const std::string& kind,
                                                      const std::filesystem::path& sourceFolder) {
  std::vector<std::filesystem::path> folders;
  if (!first.empty()) folders.push_back(first);
  const std::filesystem::path binaryFolder = executablePath().parent_path();
  if (!binaryFolder.empty()) {
    folders.push_back(binaryFolder.parent_path() / kind);
    folders.push_back(binaryFolder.parent_path() / "share" / "pluvia" / kind);
  }
  folders.push_back(sourceFolder);
  return folders;
}

}  // namespace pluvia
