// Output files (chapter 01): a failed write never destroys what was at the path. The data goes
// to a new temporary file beside the target, which is renamed over it only once every byte is
// written and the file is closed without error. Every file the course writes (images, JSON
// reports, hit and ray files) goes through write_output_file. And a failed run replaces none of
// its files: while a program runs (rt::run_main holds an OutputStaging), the renames wait until
// the run has succeeded, so a run that writes an image and then fails on its report leaves the
// image that was there before.
#pragma once

#include <cstdio>
#include <functional>
#include <string>

namespace rt {

// Writes `path` through write(file); `what` names the kind of file in errors ("PNG", "JSON
// report"). A new or existing regular file (or a symbolic link to one) is written as a
// temporary file in the same folder and renamed into place after write() returns and the
// flush and close succeed; on any failure only that temporary file is removed, and the target
// is as it was. A replaced file keeps its permission bits; a write-protected one is refused.
// The folder must let the program create a file (a writable file in a read-only folder is
// refused: writing it in place could leave it half written).
// An existing target that is not a regular file is never replaced or removed: a character
// device or a pipe (/dev/null, /dev/stdout, a FIFO) is written directly, anything else (a
// directory, a socket) is refused. write() may throw; a short write shows through ferror().
// Throws OutputError "<path>: cannot write <what> (<reason>)".
void write_output_file(const std::string& path, const std::string& what,
                       const std::function<void(std::FILE*)>& write);

// The checks of write_output_file that need no data, for a program to make before its work
// rather than after it: throws OutputError when `path` is empty, a directory, write-protected,
// not a file at all, or in a folder that does not exist.
void check_output_path(const std::string& path, const std::string& what);

// Holds back the renames of write_output_file while it lives: each file is written whole to
// its temporary file as usual, and commit() renames every one into place, in the order they
// were written (a path written twice keeps the later one). Destroyed without commit(), it
// removes them all, so no earlier file is replaced. One at a time, for the whole process
// (a second one is a logic error); files written to a stream (/dev/stdout, a pipe) go out at
// once. Not for files the reader asks for while the program runs (the window's screenshots):
// write those inside an UnstagedWrites.
class OutputStaging {
public:
  OutputStaging();
  ~OutputStaging();
  OutputStaging(const OutputStaging&) = delete;
  OutputStaging& operator=(const OutputStaging&) = delete;
  // Renames every staged file into place; throws OutputError naming the first that fails
  // (those after it are removed, those before it stay written).
  void commit();
};

// While it lives, write_output_file renames at once even under an OutputStaging.
class UnstagedWrites {
public:
  UnstagedWrites();
  ~UnstagedWrites();
  UnstagedWrites(const UnstagedWrites&) = delete;
  UnstagedWrites& operator=(const UnstagedWrites&) = delete;

private:
  bool was_paused_;
};

} // namespace rt
