// Output files (chapter 01): a failed write never destroys what was at the path. The data goes
// to a new temporary file beside the target, which is renamed over it only once every byte is
// written and the file is closed without error. Every file the course writes (images, JSON
// reports, hit and ray files) goes through write_output_file.
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

} // namespace rt
