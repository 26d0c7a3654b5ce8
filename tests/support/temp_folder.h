// A folder of its own under the system's temporary folder, made empty for one test and removed
// at its end, with the files the test writes or copies into it.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include <unistd.h>

namespace rt::testing {

class TempFolder {
public:
  // <temp>/<prefix>_<name>_<process id>: the same name in two test processes never collides.
  TempFolder(const std::string& prefix, const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              (prefix + "_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  // Writes `bytes` to `file` in the folder; returns its path.
  std::string write(const std::string& file, const std::string& bytes) const {
    const std::string path = (path_ / file).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  // Copies the file `from` into the folder as `file`; returns its path.
  std::string copy(const std::string& from, const std::string& file) const {
    std::filesystem::copy_file(from, path_ / file);
    return (path_ / file).string();
  }
  std::string path(const std::string& file) const { return (path_ / file).string(); }

private:
  std::filesystem::path path_;
};

} // namespace rt::testing
