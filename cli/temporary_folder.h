#pragma once
// A folder under the system's temporary directory that the commands' own work goes in (bench
// clips, renders, plates), removed with everything in it when the object goes, however the
// command ends.
#include <filesystem>
#include <string>

namespace pluvia::cli {

class TemporaryFolder {
 public:
  // temp_directory_path() / "<prefix>-<pid>-<serial>", made now.
  explicit TemporaryFolder(const std::string& prefix);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace pluvia::cli
