#include "contact/gmsh_reader.hpp"

#include <gmsh.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "gmsh_model.hpp"

namespace contact {
namespace {

/// Reads the tags of an ASCII .msh file line by line (MSH 2.2 and 4.1 layouts, gmsh
/// manual section "MSH file format") and throws "path:line: ..." on a tag outside [1,
/// kMaxMshTag].
class MshTagScanner {
 public:
  explicit MshTagScanner(const std::string& path) : path_(path), in_(path) {}

  void Run() {
    if (Next() != "$MeshFormat")
      Fail("expected $MeshFormat on the first line (an ASCII .msh file)");
    std::istringstream format(Next());
    double version = 0;
    int file_type = -1;
    format >> version >> file_type;
    if (!format || !(version >= 2 && version < 5))
      Fail("unsupported MSH version line '" + line_ + "' (expected 2.2 or 4.1)");
    if (file_type != 0)
      Fail(
          "binary .msh files are not accepted; write ASCII (gmsh option Mesh.Binary = "
          "0)");
    const bool v4 = version >= 4;
    while (in_ >> std::ws && !in_.eof()) {
      Next();
      if (line_ == "$Nodes") v4 ? Blocks(/*nodes=*/true) : Lines(true);
      if (line_ == "$Elements") v4 ? Blocks(false) : Lines(false);
      if (line_ == "$PhysicalNames") PhysicalNames();
    }
  }

 private:
  const std::string& Next() {
    if (!std::getline(in_, line_)) Fail("unexpected end of file");
    ++number_;
    if (!line_.empty() && line_.back() == '\r') line_.pop_back();
    return line_;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::invalid_argument(path_ + ":" + std::to_string(number_) + ": " + what);
  }
  /// A count or tag, refused beyond `limit` (read as text: no overflow on any input).
  unsigned long long Count(std::istringstream& tokens, unsigned long long limit,
                           const char* what) {
    std::string token;
    if (!(tokens >> token)) Fail(std::string("missing ") + what);
    errno = 0;
    char* end = nullptr;
    const unsigned long long value = std::strtoull(token.c_str(), &end, 10);
    if (token[0] == '-' || *end != '\0' || errno == ERANGE || value > limit)
      Fail(std::string(what) + " " + token + " lies outside [0, " +
           std::to_string(limit) + "]");
    return value;
  }
  /// MSH 4: numBlocks numItems minTag maxTag, then per block a header and its tags.
  void Blocks(bool nodes) {
    const char* tag = nodes ? "node tag" : "element tag";
    std::istringstream header(Next());
    const unsigned long long blocks = Count(header, kMaxMshTag, "number of blocks");
    const unsigned long long items =
        Count(header, kMaxMshTag, nodes ? "number of nodes" : "number of elements");
    Count(header, kMaxMshTag, tag);
    Count(header, kMaxMshTag, tag);
    for (unsigned long long b = 0; b < blocks; ++b) {
      std::istringstream block(Next());
      std::string entity_dim, entity_tag, type_or_parametric;
      block >> entity_dim >> entity_tag >> type_or_parametric;
      const unsigned long long count =
          Count(block, items, nodes ? "nodes in block" : "elements in block");
      for (unsigned long long i = 0; i < count; ++i) {
        std::istringstream tags(Next());
        Count(tags, kMaxMshTag, tag);  // element lines continue with node tags
        while (!nodes && tags >> std::ws && !tags.eof())
          Count(tags, kMaxMshTag, "node tag");
      }
      if (nodes)
        for (unsigned long long i = 0; i < count; ++i) Next();  // coordinates
    }
  }
  /// The count, then one line per group "dim tag \"name\"": dim in [0, 3] (gmsh 4.8
  /// indexes a table of four dimensions with it: 4 crashed it), tag in [1, kMaxMshTag].
  void PhysicalNames() {
    std::istringstream header(Next());
    const unsigned long long count =
        Count(header, kMaxMshTag, "number of physical names");
    for (unsigned long long i = 0; i < count; ++i) {
      std::istringstream tokens(Next());
      Count(tokens, 3, "physical group dimension");
      if (Count(tokens, kMaxMshTag, "physical group tag") == 0)
        Fail("physical group tag 0 lies outside [1, " + std::to_string(kMaxMshTag) + "]");
    }
  }
  /// MSH 2: the count, then one line per node "tag x y z" or element
  /// "tag type num_tags tags... node_tags...".
  void Lines(bool nodes) {
    std::istringstream header(Next());
    const unsigned long long count =
        Count(header, kMaxMshTag, nodes ? "number of nodes" : "number of elements");
    for (unsigned long long i = 0; i < count; ++i) {
      std::istringstream tokens(Next());
      Count(tokens, kMaxMshTag, nodes ? "node tag" : "element tag");
      if (nodes) continue;
      Count(tokens, 1000, "element type");
      const unsigned long long num_tags = Count(tokens, 100, "number of element tags");
      std::string skipped;  // physical and elementary entity tags
      for (unsigned long long k = 0; k < num_tags; ++k) tokens >> skipped;
      while (tokens >> std::ws && !tokens.eof()) Count(tokens, kMaxMshTag, "node tag");
    }
  }

  std::string path_;
  std::ifstream in_;
  std::string line_;
  long number_ = 0;
};

}  // namespace

Mesh ReadGmshMesh(const std::string& path) {
  if (!std::ifstream(path).good())
    throw std::invalid_argument("ReadGmshMesh: cannot open mesh file '" + path +
                                "' (expected a readable .msh file)");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::invalid_argument("ReadGmshMesh: '" + path + "' is not a regular file");
  if (std::filesystem::path(path).extension() != ".msh")
    throw std::invalid_argument(
        "ReadGmshMesh: '" + path +
        "' must end in .msh (gmsh would run any other file type as a "
        "script or CAD model)");
  if (std::filesystem::file_size(path, ec) > kMaxMshFileBytes)
    throw std::invalid_argument("ReadGmshMesh: '" + path + "' is larger than " +
                                std::to_string(kMaxMshFileBytes) + " bytes");
  MshTagScanner(path).Run();
  Mesh mesh;
  {
    internal::GmshSession session("contact_read");
    const std::string context = "ReadGmshMesh('" + path + "')";
    internal::CallGmsh(context, /*input_error=*/true, [&] {
      gmsh::open(path);
      mesh = internal::ExtractGmshMesh(context);
    });
  }
  try {
    ValidateMesh(mesh);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("ReadGmshMesh('" + path + "'): " + e.what());
  }
  return mesh;
}

}  // namespace contact
