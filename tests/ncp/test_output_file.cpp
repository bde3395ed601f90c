// ncp::OutputFile (ncp/output_file.hpp): what is on disk is read back independently with
// std::ifstream / std::filesystem, never taken from the class.
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "ncp/output_file.hpp"

namespace fs = std::filesystem;

namespace {

fs::path ScratchDirectory() {
  const fs::path dir =
      fs::temp_directory_path() / ("ncp-output-file-" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string Contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in),
                     std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("records committed one by one are on disk before Close") {
  const fs::path path = ScratchDirectory() / "rows.csv";
  ncp::OutputFile file = ncp::OutputFile::Open(path.string());
  file.stream() << "a,b\n";
  file.Commit();
  CHECK(Contents(path) == "a,b\n");
  file.stream() << 1 << ',' << 2.5 << '\n';
  CHECK(Contents(path) == "a,b\n");  // not committed yet
  file.Close();
  CHECK(Contents(path) == "a,b\n1,2.5\n");
  fs::remove_all(path.parent_path());
}

TEST_CASE("an atomic file appears under its name only when closed") {
  const fs::path dir = ScratchDirectory(), path = dir / "snapshot.vtu";
  const fs::path partial = dir / "snapshot.vtu.partial";
  {
    ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path.string());
    file.Write("<VTKFile/>\n");
    file.Commit();
    CHECK(!fs::exists(path));
    CHECK(fs::exists(partial));
    file.Close();
  }
  CHECK(Contents(path) == "<VTKFile/>\n");
  CHECK(!fs::exists(partial));
  {  // not closed (an exception on the way): the old file stays, the .partial goes
    ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path.string());
    file.Write("half");
    file.Commit();
  }
  CHECK(Contents(path) == "<VTKFile/>\n");
  CHECK(!fs::exists(partial));
  fs::remove_all(dir);
}

TEST_CASE("a file that cannot be created throws OutputError naming it and the reason") {
  const fs::path dir = ScratchDirectory();
  const fs::path blocker = dir / "a_file";
  std::ofstream(blocker) << "x";
  for (const fs::path& path : {blocker / "below_a_file.csv", dir})  // ENOTDIR, EISDIR
    try {
      ncp::OutputFile::Open(path.string());
      FAIL("no OutputError for " << path);
    } catch (const ncp::OutputError& e) {
      CHECK(e.path() == path.string());
      CHECK((e.error_number() == ENOTDIR || e.error_number() == EISDIR));
      CHECK(std::string(e.what()).find(path.string()) != std::string::npos);
    }
  fs::remove_all(dir);
}

TEST_CASE("a write beyond the file-size limit throws and leaves whole records only") {
  const fs::path dir = ScratchDirectory(), path = dir / "limited.csv";
  const std::string row = "0.1234567890,0.1234567890\n";  // 26 bytes
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {  // a child: the limit and SIGXFSZ must not touch the test process
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{100, 100};  // bytes: 3 rows fit, the 4th is cut at 100
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      ncp::OutputFile file = ncp::OutputFile::Open(path.string());
      for (int k = 0; k < 10; ++k) {
        file.stream() << row;
        file.Commit();
      }
      _exit(10);  // no error: wrong
    } catch (const ncp::OutputError& e) {
      _exit(e.error_number() == EFBIG && e.path() == path.string() ? 0 : 11);
    }
  }
  int status = 0;
  waitpid(child, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(Contents(path) ==
        row + row + row);  // the 4th row's first 22 bytes cut away again
  fs::remove_all(dir);
}
