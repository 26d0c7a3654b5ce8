// Output files (chapter 01): see rt/output_file.h.
#include "rt/output_file.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <system_error>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rt/error.h"

namespace rt {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& what, const std::string& path,
                       const std::string& reason) {
  throw OutputError((path.empty() ? std::string("(no file name)") : path) + ": cannot write " +
                    what + " (" + reason + ")");
}

std::string reason_of(int error) {
  return error != 0 ? std::strerror(error) : std::string("write error");
}

// What is at the path now, and where the bytes must finally go.
struct Target {
  enum class Kind { new_file, regular_file, stream } kind = Kind::new_file;
  fs::path final_path;     // a symbolic link's target, else the path itself
  fs::perms permissions{}; // of the regular file being replaced
};

Target examine(const std::string& path, const std::string& what) {
  if (path.empty()) fail(what, path, "no file name given");
  std::error_code error;
  const fs::file_status link = fs::symlink_status(path, error);
  if (error && error != std::errc::no_such_file_or_directory) fail(what, path, error.message());
  if (!fs::exists(link)) {
    const fs::path folder = fs::path(path).parent_path();
    if (!folder.empty() && !fs::is_directory(folder, error))
      fail(what, path, "the folder '" + folder.string() + "' does not exist");
    return {Target::Kind::new_file, path, {}};
  }
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) fail(what, path, "it is a symbolic link to nothing");
  if (fs::is_directory(status)) fail(what, path, "it is a directory");
  if (fs::is_character_file(status) || fs::is_fifo(status))
    return {Target::Kind::stream, path, {}};
  if (!fs::is_regular_file(status)) fail(what, path, "it is not a regular file");
  if (::access(path.c_str(), W_OK) != 0)
    fail(what, path, "it is write-protected (" + reason_of(errno) + ")");
  const fs::path final_path =
      fs::is_symlink(link) ? fs::canonical(path, error) : fs::path(path);
  if (error) fail(what, path, error.message());
  return {Target::Kind::regular_file, final_path, status.permissions()};
}

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

// Runs write(), then flushes and closes; throws OutputError with the first failure's reason.
void write_and_close(File file, const std::string& path, const std::string& what,
                     const std::function<void(std::FILE*)>& write) {
  errno = 0;
  write(file.get());
  // fflush pushes out the last buffer, so a full disk may only show here; ferror catches a
  // failed fwrite whose error the flush no longer reports.
  const bool flushed = std::fflush(file.get()) == 0 && !std::ferror(file.get());
  const int write_error = errno;
  if (std::fclose(file.release()) != 0 || !flushed)
    fail(what, path, reason_of(write_error != 0 ? write_error : errno));
}

// A name in `folder` that no other writer uses: hidden, with this process's id and a count.
fs::path temporary_name(const fs::path& final_path) {
  static std::atomic<unsigned> count{0};
  std::string name = ".";
  name += final_path.filename().string();
  name += '.';
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(count++);
  name += ".tmp";
  return final_path.parent_path() / name;
}

// The renames an OutputStaging holds back: (temporary, final path), in the order written.
struct Staged {
  std::mutex mutex;
  bool active = false;
  bool paused = false; // an UnstagedWrites is alive
  std::vector<std::pair<fs::path, fs::path>> renames;

  void discard() {
    for (const auto& [temporary, final_path] : renames) ::unlink(temporary.c_str());
    renames.clear();
  }
};

Staged& staged() {
  static Staged instance;
  return instance;
}

// Renames the temporary file into place, or, under an OutputStaging, notes it for commit().
void finish(const fs::path& temporary, const fs::path& final_path, const std::string& path,
            const std::string& what) {
  Staged& s = staged();
  {
    const std::lock_guard lock(s.mutex);
    if (s.active && !s.paused) {
      for (auto& [earlier, target] : s.renames)
        if (target == final_path) { // written again: the later bytes win
          ::unlink(earlier.c_str());
          earlier = temporary;
          return;
        }
      s.renames.emplace_back(temporary, final_path);
      return;
    }
  }
  if (std::rename(temporary.c_str(), final_path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    fail(what, path, reason_of(error));
  }
}

} // namespace

OutputStaging::OutputStaging() {
  Staged& s = staged();
  const std::lock_guard lock(s.mutex);
  if (s.active) throw Error("OutputStaging: one is alive already");
  s.active = true;
}

OutputStaging::~OutputStaging() {
  Staged& s = staged();
  const std::lock_guard lock(s.mutex);
  s.discard();
  s.active = false;
}

void OutputStaging::commit() {
  Staged& s = staged();
  const std::lock_guard lock(s.mutex);
  std::vector<std::pair<fs::path, fs::path>> renames = std::move(s.renames);
  s.renames.clear();
  for (std::size_t i = 0; i < renames.size(); ++i)
    if (std::rename(renames[i].first.c_str(), renames[i].second.c_str()) != 0) {
      const int error = errno;
      for (std::size_t k = i; k < renames.size(); ++k) ::unlink(renames[k].first.c_str());
      fail("the file", renames[i].second.string(), reason_of(error));
    }
}

UnstagedWrites::UnstagedWrites() {
  Staged& s = staged();
  const std::lock_guard lock(s.mutex);
  was_paused_ = s.paused;
  s.paused = true;
}

UnstagedWrites::~UnstagedWrites() {
  Staged& s = staged();
  const std::lock_guard lock(s.mutex);
  s.paused = was_paused_;
}

void check_output_path(const std::string& path, const std::string& what) {
  examine(path, what);
}

void write_output_file(const std::string& path, const std::string& what,
                       const std::function<void(std::FILE*)>& write) {
  const Target target = examine(path, what);
  if (target.kind == Target::Kind::stream) {
    errno = 0;
    File file(std::fopen(path.c_str(), "wb"), &std::fclose);
    if (!file) fail(what, path, reason_of(errno));
    return write_and_close(std::move(file), path, what, write);
  }

  // O_EXCL: the temporary file is new, so removing it on failure removes only what this
  // program made. Its mode is the usual 0666 less the umask, or the replaced file's.
  fs::path temporary;
  int descriptor = -1;
  for (int attempt = 0; attempt < 100 && descriptor < 0; ++attempt) {
    temporary = temporary_name(target.final_path);
    descriptor = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (descriptor < 0 && errno != EEXIST) break;
  }
  if (descriptor < 0)
    fail(what, path, "cannot create a file beside it (" + reason_of(errno) + ")");
  auto remove_temporary = [&] { ::unlink(temporary.c_str()); };
  if (target.kind == Target::Kind::regular_file)
    ::fchmod(descriptor, static_cast<mode_t>(target.permissions & fs::perms::mask));
  File file(::fdopen(descriptor, "wb"), &std::fclose);
  if (!file) {
    const int error = errno;
    ::close(descriptor);
    remove_temporary();
    fail(what, path, reason_of(error));
  }
  try {
    write_and_close(std::move(file), path, what, write);
  } catch (...) {
    remove_temporary();
    throw;
  }
  finish(temporary, target.final_path, path, what);
}

} // namespace rt
