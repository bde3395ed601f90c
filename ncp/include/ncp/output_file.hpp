/// \file output_file.hpp
/// A result file whose every write is checked: a failed or short write (disk full, file
/// size limit, directory not writable, path is a directory) throws OutputError naming the
/// file and the operating system's reason, so a run never reports success over a file
/// that lost data.
///
/// Text is formatted into stream() and goes to the file at Commit() as one record. A
/// record is written whole or not at all: after a failed write the file is cut back to
/// the end of the last committed record, so a row-per-step CSV holds only complete rows.
/// OpenAtomic writes NAME.partial and renames it to NAME on Close(), so NAME is either
/// absent, the old file, or complete; the .partial is removed when the file is not closed
/// (an exception, a failed write). POSIX only (open/write/ftruncate/rename).
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ncp {

/// A write, flush, close or rename of an output file failed.
class OutputError : public std::runtime_error {
 public:
  /// message = "<action> '<path>': <strerror(error_number)>".
  OutputError(const std::string& action, const std::string& path, int error_number);
  const std::string& path() const { return path_; }
  int error_number() const { return error_number_; }  ///< errno of the failed call

 private:
  std::string path_;
  int error_number_;
};

class OutputFile {
 public:
  /// Creates (or truncates) `path` for writing. Throws OutputError if it cannot.
  static OutputFile Open(const std::string& path);
  /// Writes `path`.partial; Close() renames it to `path`. Throws OutputError if it cannot
  /// be created.
  static OutputFile OpenAtomic(const std::string& path);
  /// Continues an existing file: cuts it to its first `keep_bytes` bytes and appends (a
  /// resumed run's CSV). Throws OutputError if it cannot be opened or cut, or holds fewer
  /// than keep_bytes bytes (EINVAL: it is not the file that was written).
  static OutputFile OpenAppend(const std::string& path, long long keep_bytes);

  OutputFile() = default;  ///< not open
  OutputFile(OutputFile&& other) noexcept;
  OutputFile& operator=(OutputFile&& other) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  /// Closes without checking (an unclosed atomic file's .partial is removed).
  ~OutputFile();

  bool is_open() const { return fd_ >= 0; }
  /// The final name (not the .partial of an atomic file).
  const std::string& path() const { return path_; }
  /// Bytes of the committed records in the file (with the kept part of OpenAppend).
  long long committed_bytes() const { return committed_bytes_; }

  /// The formatting buffer of the current record (precision and flags persist).
  std::ostream& stream() { return buffer_; }
  /// Appends raw bytes to the current record.
  void Write(std::string_view bytes) {
    buffer_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  /// Writes the current record to the file. Throws OutputError on a failed or short
  /// write, after cutting the file back to the previous record.
  void Commit();
  /// Commit(); the data is then in the operating system (there is no user-space buffer).
  void Flush() { Commit(); }
  /// Commit(), close (checked), and for an atomic file the rename. Throws OutputError.
  void Close();

 private:
  OutputFile(std::string path, std::string written_path, int fd);
  void Discard() noexcept;

  std::string path_;          // the name the result has when complete
  std::string written_path_;  // the name written to (path_ + ".partial" when atomic)
  int fd_ = -1;
  long long committed_bytes_ = 0;
  std::ostringstream buffer_;
};

/// Writes `text` to `path` atomically (OpenAtomic, Write, Close). Throws OutputError.
void WriteFileAtomically(const std::string& path, std::string_view text);

}  // namespace ncp
