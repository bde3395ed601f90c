#include "ncp/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

namespace ncp {

OutputError::OutputError(const std::string& action, const std::string& path,
                         int error_number)
    : std::runtime_error(action + " '" + path + "': " + std::strerror(error_number)),
      path_(path),
      error_number_(error_number) {}

namespace {

int OpenForWriting(const std::string& path) {
  int fd;
  do {
    fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) throw OutputError("cannot open", path, errno);
  return fd;
}

}  // namespace

OutputFile::OutputFile(std::string path, std::string written_path, int fd)
    : path_(std::move(path)), written_path_(std::move(written_path)), fd_(fd) {}

OutputFile OutputFile::Open(const std::string& path) {
  return OutputFile(path, path, OpenForWriting(path));
}

OutputFile OutputFile::OpenAtomic(const std::string& path) {
  struct stat existing {};
  if (::stat(path.c_str(), &existing) == 0 &&
      S_ISDIR(existing.st_mode))  // rename would fail late
    throw OutputError("cannot open", path, EISDIR);
  const std::string partial = path + ".partial";
  return OutputFile(path, partial, OpenForWriting(partial));
}

OutputFile OutputFile::OpenAppend(const std::string& path, long long keep_bytes) {
  int fd;
  do {
    fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) throw OutputError("cannot open", path, errno);
  OutputFile file(path, path, fd);  // (closes fd on a throw below)
  struct stat existing {};
  if (::fstat(fd, &existing) != 0) throw OutputError("cannot inspect", path, errno);
  if (keep_bytes < 0 || existing.st_size < keep_bytes)
    throw OutputError("shorter than expected", path, EINVAL);
  if (::ftruncate(fd, static_cast<off_t>(keep_bytes)) != 0)
    throw OutputError("cannot cut back", path, errno);
  if (::lseek(fd, static_cast<off_t>(keep_bytes), SEEK_SET) < 0)
    throw OutputError("cannot seek in", path, errno);
  file.committed_bytes_ = keep_bytes;
  return file;
}

OutputFile::OutputFile(OutputFile&& other) noexcept
    : path_(std::move(other.path_)),
      written_path_(std::move(other.written_path_)),
      fd_(std::exchange(other.fd_, -1)),
      committed_bytes_(other.committed_bytes_),
      buffer_(std::move(other.buffer_)) {}

OutputFile& OutputFile::operator=(OutputFile&& other) noexcept {
  if (this != &other) {
    Discard();
    path_ = std::move(other.path_);
    written_path_ = std::move(other.written_path_);
    fd_ = std::exchange(other.fd_, -1);
    committed_bytes_ = other.committed_bytes_;
    buffer_ = std::move(other.buffer_);
  }
  return *this;
}

OutputFile::~OutputFile() { Discard(); }

void OutputFile::Discard() noexcept {
  if (fd_ < 0) return;
  ::close(fd_);
  fd_ = -1;
  if (written_path_ != path_) std::remove(written_path_.c_str());
}

void OutputFile::Commit() {
  if (fd_ < 0) throw OutputError("not open for writing", path_, EBADF);
  const std::string record = buffer_.str();
  buffer_.str(std::string());
  size_t done = 0;
  while (done < record.size()) {
    const ssize_t n = ::write(fd_, record.data() + done, record.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error =
          n < 0 ? errno : ENOSPC;  // write returning 0 for a regular file: no space
      // Keep only whole records: cut the file back to the end of the last committed one.
      if (::ftruncate(fd_, static_cast<off_t>(committed_bytes_)) == 0)
        ::lseek(fd_, static_cast<off_t>(committed_bytes_), SEEK_SET);
      throw OutputError("cannot write", written_path_, error);
    }
    done += static_cast<size_t>(n);
  }
  committed_bytes_ += static_cast<long long>(record.size());
}

void OutputFile::Close() {
  Commit();
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0 &&
      errno != EINTR) {  // close's EINTR: the descriptor is released on Linux
    const int error = errno;
    if (written_path_ != path_) std::remove(written_path_.c_str());
    throw OutputError("cannot close", written_path_, error);
  }
  if (written_path_ != path_ && std::rename(written_path_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    std::remove(written_path_.c_str());
    throw OutputError("cannot rename '" + written_path_ + "' to", path_, error);
  }
}

void WriteFileAtomically(const std::string& path, std::string_view text) {
  OutputFile file = OutputFile::OpenAtomic(path);
  file.Write(text);
  file.Close();
}

}  // namespace ncp
