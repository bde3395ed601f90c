#include "contact/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <toml.hpp>

#include "contact/contact_boundary.hpp"
#include "contact/dof_map.hpp"
#include "contact/elastic_body.hpp"
#include "contact/gmsh_reader.hpp"
#include "contact/vtk_writer.hpp"
#include "text_format.hpp"

namespace contact {
namespace {

namespace fs = std::filesystem;

/// Integers in full (4294967297, not 4.29497e+09), other numbers with 6 digits.
std::string Str(double x) {
  if (x == std::floor(x) && std::abs(x) < 1e15) return std::to_string(static_cast<long long>(x));
  return internal::FormatShort(x);
}

/// The accepted interval of a scene number and its SI unit: every number of a scene is read
/// through one of these, so a new key gets its range check and its one-line message
/// "file:line: 'table.key' = value unit is outside the accepted range [min, max] unit".
/// The bounds keep every derived quantity (stiffness E/h^2, omega_max^2 = E/(rho h^2),
/// step counts) finite in double precision; they are far outside any physical use.
struct Range {
  double min, max;
  const char* unit;
  bool min_open = false, max_open = false;  ///< "(" or ")" instead of "[" or "]"
  bool Contains(double x) const {
    return (min_open ? x > min : x >= min) && (max_open ? x < max : x <= max);
  }
  std::string Describe() const {
    const std::string u = unit[0] ? std::string(" ") + unit : "";
    return std::string(" the accepted range ") + (min_open ? "(" : "[") + Str(min) + ", " + Str(max) + (max_open ? ")" : "]") + u;
  }
};
// A scene may be written in any consistent unit system (SI, mm-tonne-s with N and MPa, a body
// scaled by 1e-3 ...): the unit shown is SI's, and each range spans the values of every such
// system by many orders of magnitude while keeping E / (rho h^2) and the step counts finite.
constexpr double kMaxLength = 1e9;  // coordinates and sizes of a scene
const Range kCoordinate{-kMaxLength, kMaxLength, "m"};
const Range kLength{1e-9, kMaxLength, "m"};
const Range kDirection{-1e6, 1e6, ""};  // normals and axes, normalized by the obstacle
const Range kModulus{1e-12, 1e18, "Pa"};  // Young's modulus (steel 2.1e11 Pa = 2.1e5 MPa)
const Range kDensity{1e-15, 1e12, "kg/m^3"};  // (osmium 22590 kg/m^3 = 2.26e-8 t/mm^3)
const Range kPoisson{-1.0, 0.5, "", true, true};
const Range kForceDensity{-1e18, 1e18, "N/m^3"};
const Range kStress{-1e18, 1e18, "Pa"};
const Range kCurvature{-1e15, 1e15, "1/m"};
const Range kFriction{0.0, 100.0, ""};
const Range kTime{0.0, 1e9, "s", true};
const Range kTimeOrZero{0.0, 1e9, "s"};
const Range kVelocity{-1e9, 1e9, "m/s"};
const Range kRelativeTolerance{0.0, 1.0, "", true};
const Range kIterations{1, 1e6, ""};

/// A TOML table that remembers which keys were read, so that unknown keys (typos) can be
/// reported by name, and that names the key in every error.
class Table {
 public:
  Table(const toml::value* value, std::string path, std::string file)
      : value_(value), path_(std::move(path)), file_(std::move(file)) {}

  bool Has(const std::string& key) const {
    return value_ != nullptr && value_->as_table().count(key) > 0;
  }

  const toml::value& Get(const std::string& key) const {
    used_.insert(key);
    if (!Has(key)) Fail(key, "is missing" + TypoHint(key));
    return value_->as_table().at(key);
  }

  /// A number in `range` (integers are accepted and converted exactly when |n| < 2^53).
  double Number(const std::string& key, const Range& range) const {
    const toml::value& v = Get(key);
    const double x = ToDouble(key, v, v);
    CheckRange(key, x, range, v);
    return x;
  }
  double Number(const std::string& key, const Range& range, double fallback) const {
    return Has(key) ? Number(key, range) : (used_.insert(key), fallback);
  }
  /// An integer in [range.min, range.max], checked on the 64-bit value before narrowing.
  int Integer(const std::string& key, const Range& range, int fallback) const {
    if (!Has(key)) return used_.insert(key), fallback;
    const toml::value& v = Get(key);
    if (!v.is_integer()) Fail(key, "must be an integer in" + range.Describe(), &v);
    const double x = ToDouble(key, v, v);
    CheckRange(key, x, range, v);
    return static_cast<int>(v.as_integer());
  }
  bool Boolean(const std::string& key, bool fallback) const {
    if (!Has(key)) return used_.insert(key), fallback;
    const toml::value& v = Get(key);
    if (!v.is_boolean()) Fail(key, "must be true or false", &v);
    return v.as_boolean();
  }
  std::string String(const std::string& key) const {
    const toml::value& v = Get(key);
    if (!v.is_string()) Fail(key, "must be a string", &v);
    return v.as_string().str;
  }
  std::string String(const std::string& key, const std::string& fallback) const {
    return Has(key) ? String(key) : (used_.insert(key), fallback);
  }
  /// One of `choices`.
  std::string Choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& fallback = "") const {
    const std::string s = fallback.empty() || Has(key) ? String(key) : (used_.insert(key), fallback);
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
      std::string list;
      for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
      Fail(key, "must be one of " + list + ", got \"" + s + "\"", &Get(key));
    }
    return s;
  }
  /// An array of numbers, each in `range` (and `expected_size` entries if >= 0).
  std::vector<double> Numbers(const std::string& key, const Range& range, int expected_size = -1) const {
    const toml::value& v = Get(key);
    if (!v.is_array()) Fail(key, "must be an array of numbers in" + range.Describe(), &v);
    if (expected_size >= 0 && static_cast<int>(v.as_array().size()) != expected_size)
      Fail(key, "must have " + std::to_string(expected_size) + " entries, got " +
                    std::to_string(v.as_array().size()), &v);
    std::vector<double> out;
    for (const toml::value& e : v.as_array()) {
      out.push_back(ToDouble(key, e, v));
      CheckRange(key, out.back(), range, v, out.size() - 1);
    }
    return out;
  }
  Eigen::VectorXd Vec(const std::string& key, const Range& range, int size) const {
    const std::vector<double> v = Numbers(key, range, size);
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  std::vector<std::string> Strings(const std::string& key) const {
    if (!Has(key)) return used_.insert(key), std::vector<std::string>{};
    const toml::value& v = Get(key);
    if (!v.is_array()) Fail(key, "must be an array of strings", &v);
    std::vector<std::string> out;
    for (const toml::value& e : v.as_array()) {
      if (!e.is_string()) Fail(key, "must be an array of strings", &v);
      out.push_back(e.as_string().str);
    }
    return out;
  }
  Table Sub(const std::string& key, bool required) const {
    if (!Has(key)) {
      if (required) Fail(key, "(a table) is missing");
      used_.insert(key);
      return Table(nullptr, Join(key), file_);
    }
    const toml::value& v = Get(key);
    if (!v.is_table()) Fail(key, "must be a table [" + Join(key) + "]", &v);
    return Table(&v, Join(key), file_);
  }
  bool present() const { return value_ != nullptr; }

  /// Throws on keys that were never read.
  void RejectUnknownKeys(const std::string& known_hint = "") const {
    if (value_ == nullptr) return;
    for (const auto& [key, v] : value_->as_table()) {
      if (used_.count(key)) continue;
      std::string known;
      for (const auto& k : used_) known += (known.empty() ? "" : ", ") + k;
      throw SceneError(file_ + ":" + std::to_string(v.location().line()) + ": unknown key '" +
                       Join(key) + "'" + (known.empty() ? "" : " (known keys here: " + known + ")") +
                       known_hint);
    }
  }

  [[noreturn]] void Fail(const std::string& key, const std::string& what,
                         const toml::value* at = nullptr) const {
    // The value's own source: the scene file, or "command line (table.key)" for an override.
    const std::string where =
        at ? at->location().file_name() + ":" + std::to_string(at->location().line()) : file_;
    throw SceneError(where + ": '" + Join(key) + "' " + what);
  }

 private:
  /// The value of a TOML number as a double. toml11 3.7 saturates an integer literal beyond
  /// the int64 range to INT64_MIN / INT64_MAX without an error, so those two are refused.
  double ToDouble(const std::string& key, const toml::value& e, const toml::value& at) const {
    if (e.is_floating()) return e.as_floating();
    if (!e.is_integer()) Fail(key, "must be a number, got a " + TypeName(e), &at);
    const std::int64_t i = e.as_integer();
    if (i == std::numeric_limits<std::int64_t>::max() || i == std::numeric_limits<std::int64_t>::min())
      Fail(key, "is an integer literal beyond the 64-bit range [-2^63, 2^63 - 1]", &at);
    return static_cast<double>(i);
  }
  void CheckRange(const std::string& key, double x, const Range& range, const toml::value& at,
                  size_t entry = static_cast<size_t>(-1)) const {
    if (range.Contains(x)) return;
    const std::string which = entry == static_cast<size_t>(-1) ? "" : "entry " + std::to_string(entry) + " ";
    Fail(key, which + "= " + Str(x) + (range.unit[0] ? std::string(" ") + range.unit : "") +
                  " is outside" + range.Describe(), &at);
  }
  static std::string TypeName(const toml::value& v) {
    std::ostringstream s;
    s << v.type();
    return s.str();
  }
  std::string Join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  /// " (found 'youngs_modulus' in this table: a typo?)" for a present key within edit
  /// distance 2 of the missing one.
  std::string TypoHint(const std::string& missing) const {
    if (value_ == nullptr) return "";
    for (const auto& [key, v] : value_->as_table()) {
      (void)v;
      const size_t n = key.size(), m = missing.size();
      std::vector<size_t> row(m + 1);
      for (size_t j = 0; j <= m; ++j) row[j] = j;
      for (size_t i = 1; i <= n; ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= m; ++j) {
          const size_t above = row[j];
          row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (key[i - 1] == missing[j - 1] ? 0 : 1)});
          diagonal = above;
        }
      }
      if (row[m] <= 2) return " (found '" + Join(key) + "' instead: a typo?)";
    }
    return "";
  }
  const toml::value* value_;
  std::string path_, file_;
  mutable std::set<std::string> used_;
};

Side ParseSide(const Table& t, const std::string& key, const std::string& s, int dim) {
  static const std::map<std::string, Side> sides = {{"xmin", Side::kXMin}, {"xmax", Side::kXMax},
                                                    {"ymin", Side::kYMin}, {"ymax", Side::kYMax},
                                                    {"zmin", Side::kZMin}, {"zmax", Side::kZMax}};
  const auto it = sides.find(s);
  if (it == sides.end() || (dim == 2 && (s == "zmin" || s == "zmax")))
    t.Fail(key, "has an unknown side \"" + s + "\" (xmin, xmax, ymin, ymax" +
                    (dim == 3 ? ", zmin, zmax)" : ")"));
  return it->second;
}

ElementType ParseElement(const Table& t, int dim) {
  const std::string e = dim == 2 ? t.Choice("element", {"quad4", "tri3"}, "quad4")
                                 : t.Choice("element", {"hex8", "tet4"}, "hex8");
  if (e == "quad4") return ElementType::kQuadrilateral4;
  if (e == "tri3") return ElementType::kTriangle3;
  if (e == "hex8") return ElementType::kHexahedron8;
  return ElementType::kTetrahedron4;
}

void ReadGeometry(const Table& g, Scene* s) {
  const std::string type = g.Choice("type", {"rectangle", "box", "msh"});
  if (type == "msh") {
    s->msh_file = g.String("file");
    s->dim = g.Integer("dimension", Range{2, 3, ""}, 0);
    if (s->dim != 2 && s->dim != 3) g.Fail("dimension", "must be 2 or 3 for a .msh geometry");
  } else {
    s->dim = type == "rectangle" ? 2 : 3;
    std::map<Side, BoundaryRole> roles;
    const std::pair<const char*, BoundaryRole> role_keys[] = {
        {"fixed", BoundaryRole::kFixed}, {"load", BoundaryRole::kLoad}, {"contact", BoundaryRole::kContact}};
    for (const auto& [key, role] : role_keys)
      for (const std::string& side : g.Strings(key)) {
        const Side sd = ParseSide(g, key, side, s->dim);
        if (roles.count(sd)) g.Fail(key, "assigns side " + side + " a second role");
        roles[sd] = role;
      }
    const Eigen::VectorXd origin = g.Has("origin") ? g.Vec("origin", kCoordinate, s->dim) : Eigen::VectorXd::Zero(s->dim);
    const Eigen::VectorXd size = g.Vec("size", kLength, s->dim);
    const std::vector<double> cells = g.Numbers("cells", Range{1, kMaxGeneratedCells, ""}, s->dim);
    for (double c : cells)
      if (c != std::floor(c)) g.Fail("cells", "entries must be integers, got " + Str(c), &g.Get("cells"));
    const std::string grid_error = CheckGridLimits(std::vector<double>(size.data(), size.data() + s->dim), cells);
    if (!grid_error.empty()) g.Fail("size", "and 'cells': " + grid_error, &g.Get("cells"));
    const bool structured = g.Choice("topology", {"structured", "unstructured"}, "structured") == "structured";
    if (s->dim == 2) {
      RectangleMeshOptions o;
      for (int k = 0; k < 2; ++k) {
        o.origin[static_cast<size_t>(k)] = origin(k);
        o.size[static_cast<size_t>(k)] = size(k);
        o.cells[static_cast<size_t>(k)] = static_cast<int>(cells[static_cast<size_t>(k)]);
      }
      o.element_type = ParseElement(g, 2);
      o.topology = structured ? MeshTopology::kStructured : MeshTopology::kUnstructured;
      o.side_roles = roles;
      s->rectangle = o;
    } else {
      BoxMeshOptions o;
      for (int k = 0; k < 3; ++k) {
        o.origin[static_cast<size_t>(k)] = origin(k);
        o.size[static_cast<size_t>(k)] = size(k);
        o.cells[static_cast<size_t>(k)] = static_cast<int>(cells[static_cast<size_t>(k)]);
      }
      o.element_type = ParseElement(g, 3);
      o.topology = structured ? MeshTopology::kStructured : MeshTopology::kUnstructured;
      o.side_roles = roles;
      s->box = o;
    }
  }
  for (double c : g.Has("fixed_components") ? g.Numbers("fixed_components", Range{0, 2, ""}) : std::vector<double>{}) {
    if (c != std::floor(c) || c < 0 || c >= s->dim)
      g.Fail("fixed_components", "entries must be components 0.." + std::to_string(s->dim - 1));
    s->fixed_components.push_back(static_cast<int>(c));
  }
  g.RejectUnknownKeys();
}

std::shared_ptr<RigidObstacle> ReadObstacle(const Table& o, int dim) {
  const std::string type = o.Choice("type", {"plane", "parabola", "sphere", "cylinder"});
  std::shared_ptr<RigidObstacle> obstacle;
  try {
    if (type == "plane") {
      // The obstacle fills {y : n . y <= offset}; the body lies where n . x >= offset.
      obstacle = std::make_shared<HalfSpace>(o.Vec("normal", kDirection, dim), o.Number("offset", kCoordinate));
    } else if (type == "parabola") {
      obstacle = std::make_shared<ParabolaObstacle>(dim, o.Number("vertex", kCoordinate), o.Number("coefficient", kCurvature));
    } else if (type == "sphere") {
      obstacle = std::make_shared<SphereObstacle>(o.Vec("center", kCoordinate, dim), o.Number("radius", kLength));
    } else {
      if (dim != 3) o.Fail("type", "\"cylinder\" needs a 3D geometry");
      obstacle = std::make_shared<CylinderObstacle>(o.Vec("axis_point", kCoordinate, 3), o.Vec("axis_direction", kDirection, 3),
                                                    o.Number("radius", kLength));
    }
  } catch (const SceneError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    o.Fail("type", std::string("= \"") + type + "\": " + e.what());
  }
  return obstacle;
}

/// The deepest nesting of arrays and inline tables in TOML text, with the line where it is
/// reached; strings and comments are skipped. toml11 parses nested values recursively, so
/// a few hundred thousand '[' overflow the stack: this runs before it.
std::pair<int, int> MaxNestingDepth(const std::string& text) {
  int depth = 0, deepest = 0, line = 1, deepest_line = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const std::string quote = text.compare(i, 3, std::string(3, c)) == 0 ? std::string(3, c) : std::string(1, c);
      for (i += quote.size(); i < text.size() && text.compare(i, quote.size(), quote) != 0; ++i) {
        if (text[i] == '\n') ++line;
        if (c == '"' && text[i] == '\\') ++i;  // an escape in a basic string
      }
      i += quote.size() - 1;
    } else if (c == '[' || c == '{') {
      if (++depth > deepest) deepest = depth, deepest_line = line;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return {deepest, deepest_line};
}

/// The text of a scene file, refused before parsing if it is not a regular file, larger
/// than kMaxSceneFileBytes, or nested deeper than kMaxSceneNesting.
std::string ReadSceneText(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) throw SceneError(path + ": cannot read scene file: no such file");
  if (!fs::is_regular_file(status))
    throw SceneError(path + ": cannot read scene file: not a regular file (a directory?)");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > kMaxSceneFileBytes)
    throw SceneError(path + ": scene file of " + std::to_string(bytes) + " bytes; at most " +
                     std::to_string(kMaxSceneFileBytes) + " bytes are accepted");
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw SceneError(path + ": cannot read scene file");
  const auto [depth, line] = MaxNestingDepth(text);
  if (depth > kMaxSceneNesting)
    throw SceneError(path + ":" + std::to_string(line) + ": arrays or inline tables nested " +
                     std::to_string(depth) + " deep; at most " + std::to_string(kMaxSceneNesting) +
                     " levels are accepted");
  return text;
}

}  // namespace

Scene LoadScene(const std::string& path, const SceneOverrides& overrides) {
  toml::value root;
  std::istringstream text(ReadSceneText(path));
  try {
    root = toml::parse(text, path);
  } catch (const std::exception& e) {
    throw SceneError("cannot read scene file " + path + ": " + e.what());
  }
  // Each override "table.key" = TOML literal replaces the file's value before validation,
  // so it is checked (and named in messages, at "command line") like a value of the file.
  for (const auto& [dotted, literal] : overrides) {
    const size_t dot = dotted.find('.');
    if (dot == std::string::npos || dotted.find('.', dot + 1) != std::string::npos)
      throw SceneError("command line: override key '" + dotted + "' must be table.key");
    std::istringstream value_text("value = " + literal);
    toml::value parsed;
    try {
      parsed = toml::parse(value_text, "command line (" + dotted + ")");
    } catch (const std::exception& e) {
      throw SceneError("command line: '" + dotted + "' = " + literal + " is not a TOML value: " + e.what());
    }
    toml::value& table = root.as_table()[dotted.substr(0, dot)];
    if (table.is_uninitialized()) table = toml::table{};
    if (!table.is_table()) throw SceneError(path + ": '" + dotted.substr(0, dot) + "' must be a table");
    table.as_table()[dotted.substr(dot + 1)] = parsed.as_table().at("value");
  }
  Scene s;
  s.source = path;
  const fs::path base = fs::path(path).parent_path();
  const Table top(&root, "", path);
  s.name = top.String("name", fs::path(path).stem().string());

  ReadGeometry(top.Sub("geometry", true), &s);
  if (!s.msh_file.empty() && fs::path(s.msh_file).is_relative()) s.msh_file = (base / s.msh_file).string();

  const Table m = top.Sub("material", true);
  s.material.youngs_modulus = m.Number("young_modulus", kModulus);
  s.material.poisson_ratio = m.Number("poisson_ratio", kPoisson);
  s.material.density = m.Number("density", kDensity);
  s.mass = m.Choice("mass", {"consistent", "lumped"}, "consistent") == "lumped" ? MassKind::kLumped : MassKind::kConsistent;
  if (s.dim == 2) {
    s.plane.model = m.Choice("plane", {"strain", "stress"}, "strain") == "stress" ? PlaneModel::kPlaneStress : PlaneModel::kPlaneStrain;
    s.plane.thickness = m.Number("thickness", kLength, 1.0);
  }
  m.RejectUnknownKeys();

  const Table l = top.Sub("loads", false);
  s.body_force = l.Has("body_force") ? l.Vec("body_force", kForceDensity, s.dim) : Eigen::VectorXd::Zero(s.dim);
  if (l.Has("traction")) s.traction = l.Vec("traction", kStress, s.dim);
  const std::string history = l.Choice("history", {"constant", "step", "ramp"}, "constant");
  s.load_history = history == "step" ? LoadHistory::kStep : history == "ramp" ? LoadHistory::kRamp : LoadHistory::kConstant;
  if (s.load_history == LoadHistory::kRamp) s.ramp_time = l.Number("ramp_time", kTime);
  l.RejectUnknownKeys();

  const Table o = top.Sub("obstacle", true);
  s.obstacle = ReadObstacle(o, s.dim);
  s.normal_source = o.Choice("normal_source", {"body", "obstacle"}, "body") == "obstacle" ? NormalSource::kObstacle : NormalSource::kBody;
  o.RejectUnknownKeys();

  const Table f = top.Sub("friction", false);
  s.friction_coefficient = f.Number("coefficient", kFriction, 0.0);
  f.RejectUnknownKeys();

  const Table t = top.Sub("time", true);
  s.dynamics.dt = t.Number("dt", kTime);
  s.dynamics.end_time = t.Number("end_time", kTime);
  const double steps = std::ceil(s.dynamics.end_time / s.dynamics.dt);
  if (steps > kMaxTimeSteps)
    t.Fail("dt", "= " + Str(s.dynamics.dt) + " s with time.end_time = " + Str(s.dynamics.end_time) +
                     " s gives " + Str(steps) + " time steps; at most " + Str(kMaxTimeSteps) +
                     " are accepted (one step record each)", &t.Get("dt"));
  s.dynamics.allow_unstable_time_step = t.Boolean("allow_unstable", false);
  const std::string initial = t.Choice("initial_state", {"static", "velocity"}, "static");
  if (initial == "velocity") {
    s.dynamics.initial_state = InitialState::kPrescribed;
    s.initial_velocity = t.Vec("initial_velocity", kVelocity, s.dim);
  }
  t.RejectUnknownKeys();

  const Table v = top.Sub("solver", false);
  const std::string method = v.Choice("method", {"fb", "min", "penalized-fb", "ipopt"}, "fb");
  s.dynamics.solver = method == "min" ? StepSolver::kMin
                      : method == "penalized-fb" ? StepSolver::kPenalizedFischerBurmeister
                      : method == "ipopt" ? StepSolver::kIpopt : StepSolver::kFischerBurmeister;
  if (s.dynamics.solver == StepSolver::kIpopt && s.friction_coefficient > 0)
    v.Fail("method", "= \"ipopt\" solves frictionless steps only, but friction.coefficient = " +
                         std::to_string(s.friction_coefficient));
  s.dynamics.ncp.tolerance = v.Number("tolerance", kRelativeTolerance, 1e-10);
  s.dynamics.ncp.max_iterations = v.Integer("max_iterations", kIterations, 500);
  const std::string ls = v.Choice("linear_solver", {"auto", "dense", "sparse-lu", "umfpack", "klu"}, "auto");
  s.dynamics.ncp.linear_solver = ls == "dense" ? ncp::LinearSolverType::kDenseLU
                                 : ls == "sparse-lu" ? ncp::LinearSolverType::kSparseLU
                                 : ls == "umfpack" ? ncp::LinearSolverType::kUmfpack
                                 : ls == "klu" ? ncp::LinearSolverType::kKlu : ncp::LinearSolverType::kAuto;
  const std::string step = v.Choice("step", {"auto", "condensed", "sparse", "full", "explicit"}, "auto");
  s.dynamics.step_method = step == "full"        ? StepMethod::kFull
                           : step == "explicit"  ? StepMethod::kExplicit
                           : step == "sparse"    ? StepMethod::kSparse
                           : step == "condensed" ? StepMethod::kCondensed
                                                 : StepMethod::kAuto;
  if (s.dynamics.step_method == StepMethod::kExplicit && s.mass != MassKind::kLumped)
    v.Fail("step", "= \"explicit\" needs material.mass = \"lumped\"");
  const std::string friction = v.Choice("friction", {"default", "eq94", "coulomb-fc"}, "default");
  if (friction != "default")
    s.dynamics.friction_formulation =
        friction == "eq94" ? FrictionFormulation::kEq94 : FrictionFormulation::kCoulombFc;
  const StepMethod chosen = s.dynamics.step_method;
  if (friction == "coulomb-fc" && chosen != StepMethod::kCondensed && chosen != StepMethod::kSparse && chosen != StepMethod::kAuto)
    v.Fail("friction", "= \"coulomb-fc\" needs solver.step = \"auto\", \"condensed\" or \"sparse\", got \"" +
                           step + "\"");
  if (friction == "eq94" && chosen == StepMethod::kSparse)
    v.Fail("friction", "= \"eq94\" needs solver.step = \"auto\", \"condensed\" or \"full\" (the sparse step "
                       "solves implicit Coulomb only), got \"sparse\"");
  s.dynamics.ncp.log_to_stderr = v.Boolean("log_iterations", false);
  s.dynamics.compare_with_ipopt = v.Boolean("compare_with_ipopt", false);
  if (s.dynamics.compare_with_ipopt && s.friction_coefficient > 0)
    v.Fail("compare_with_ipopt", "needs a frictionless scene");
  v.RejectUnknownKeys();

  const Table out = top.Sub("output", false);
  if (out.Has("directory")) {
    const fs::path d = out.String("directory");
    s.output_directory = (d.is_relative() ? base / d : d).string();
  }
  if (out.Has("stress_times")) s.stress_times = out.Numbers("stress_times", kTimeOrZero);
  s.snapshot_every = out.Integer("snapshot_every", Range{0, kMaxTimeSteps, ""}, 0);
  if (out.Has("marked_point")) s.marked_point = out.Vec("marked_point", kCoordinate, s.dim);
  out.RejectUnknownKeys();

  top.RejectUnknownKeys();
  return s;
}

// ---------------------------------------------------------------------------------------

namespace {

/// Runs `build`; a std::invalid_argument from the mesh or the model (a missing group, an
/// empty contact set ...) becomes a SceneError that names the scene file and the mesh file.
template <typename Build>
auto NamingTheScene(const Scene& scene, Build build) {
  try {
    return build();
  } catch (const SceneError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    const std::string mesh = scene.msh_file.empty() ? "" : " (mesh " + scene.msh_file + ")";
    throw SceneError(scene.source + mesh + ": " + e.what());
  }
}

SceneModel BuildModel(const Scene& scene, Mesh mesh);

}  // namespace

SceneModel BuildSceneModel(const Scene& scene) {
  return NamingTheScene(scene, [&] {
    return BuildModel(scene, !scene.msh_file.empty() ? ReadGmshMesh(scene.msh_file)
                             : scene.rectangle       ? MakeRectangleMesh(*scene.rectangle)
                                                     : MakeBoxMesh(*scene.box));
  });
}

SceneModel BuildSceneModel(const Scene& scene, Mesh mesh) {
  return NamingTheScene(scene, [&] { return BuildModel(scene, std::move(mesh)); });
}

namespace {

SceneModel BuildModel(const Scene& scene, Mesh mesh) {
  SceneModel out;
  if (mesh.dim != scene.dim)
    throw SceneError(scene.source + ": the mesh is " + std::to_string(mesh.dim) +
                     "D but the scene is " + std::to_string(scene.dim) + "D");
  out.body = std::make_unique<ElasticBody>(std::move(mesh), scene.material, scene.plane);
  const ElasticBody& body = *out.body;
  const Mesh& M = body.mesh();
  const int dim = M.dim;
  std::vector<DirichletCondition> conditions;
  if (M.HasBoundaryGroup(kFixedGroup)) {
    DirichletCondition fixed;
    fixed.components = scene.fixed_components;
    conditions.push_back(fixed);
  }
  out.dofs = MakeDofMap(M, conditions);
  out.boundary = MakeContactBoundary(body);
  out.frames = MakeContactFrames(M, out.boundary, out.dofs, *scene.obstacle, scene.normal_source);
  if (out.frames.nodes.empty())
    throw SceneError(scene.source + ": no contact node is left after removing the " +
                     std::to_string(out.frames.excluded_mesh_nodes.size()) +
                     " nodes constrained by the 'fixed' group");

  DynamicModel& model = out.model;
  model.dim = dim;
  // Without constrained dofs A_FF = A: no copies (K is the largest object of the model).
  const bool all_free = out.dofs.NumConstrainedDofs() == 0;
  SparseMatrix K_full = body.StiffnessMatrix();
  if (scene.mass == MassKind::kLumped) {
    const Vector lumped = body.LumpedMass();
    SparseMatrix L(lumped.size(), lumped.size());
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index i = 0; i < lumped.size(); ++i) t.emplace_back(static_cast<int>(i), static_cast<int>(i), lumped(i));
    L.setFromTriplets(t.begin(), t.end());
    model.M = out.dofs.RestrictMatrix(L);
  } else {
    SparseMatrix M_full = body.ConsistentMassMatrix();
    if (all_free) model.M.swap(M_full);
    else model.M = out.dofs.RestrictMatrix(M_full);
  }
  Vector f_full = body.BodyForceLoad(scene.body_force);
  if (scene.traction.size()) f_full += body.TractionLoad(scene.traction);
  const Vector f_free = out.dofs.RestrictLoad(K_full, f_full);
  if (all_free) model.K.swap(K_full);  // (swap: Eigen 3.4's SparseMatrix has no move constructor)
  else model.K = out.dofs.RestrictMatrix(K_full);
  const double t0 = scene.dynamics.start_time;
  const LoadHistory history = scene.load_history;
  const double ramp = scene.ramp_time;
  model.load = [f_free, t0, history, ramp](double t, Eigen::VectorXd* f) {
    double factor = 1.0;
    if (history == LoadHistory::kStep) factor = t > t0 + 1e-12 * std::max(1.0, std::abs(t0)) ? 1.0 : 0.0;
    if (history == LoadHistory::kRamp) factor = std::min(std::max((t - t0) / ramp, 0.0), 1.0);
    *f = factor * f_free;
  };
  model.contact_nodes = out.frames.nodes;

  out.options = scene.dynamics;
  out.options.friction_coefficient = scene.friction_coefficient;
  if (out.options.initial_state == InitialState::kPrescribed) {
    out.options.u0 = Eigen::VectorXd::Zero(out.dofs.NumFreeDofs());
    Vector v_full = Vector::Zero(M.NumDofs());
    for (int i = 0; i < M.NumNodes(); ++i) v_full.segment(dim * i, dim) = scene.initial_velocity;
    out.options.v0 = out.dofs.RestrictVector(v_full);
  }
  return out;
}

}  // namespace

SceneResult RunScene(const Scene& scene, bool progress) {
  SceneResult result;
  SceneModel built = BuildSceneModel(scene);
  const Mesh& M = built.body->mesh();
  const int dim = M.dim;
  const DofMap& dofs = built.dofs;
  const ContactFrames& frames = built.frames;
  DynamicOptions& options = built.options;
  options.progress = progress;
  result.num_dofs = M.NumDofs();
  result.num_free_dofs = dofs.NumFreeDofs();
  result.num_contact_nodes = static_cast<int>(frames.nodes.size());
  result.num_elements = M.NumElements();

  // Marked node: the contact node nearest to marked_point (the first one if every distance
  // compares equal, e.g. overflows to inf; BuildSceneModel guarantees one contact node).
  int marked = -1;
  if (scene.marked_point) {
    double best = std::numeric_limits<double>::infinity();
    marked = 0;
    for (size_t c = 0; c < frames.nodes.size(); ++c) {
      const double d = (M.nodes.col(frames.nodes[c].node) - *scene.marked_point).norm();
      if (d < best) best = d, marked = static_cast<int>(c);
    }
    result.marked_node = frames.nodes[static_cast<size_t>(marked)].node;
  }

  // Outputs.
  const bool write = !scene.output_directory.empty();
  std::ofstream steps_csv, stress_csv, history_csv, displacement_csv;
  const fs::path dir = scene.output_directory;
  auto open = [&](std::ofstream& s, const std::string& name, const std::string& header) {
    const std::string p = (dir / name).string();
    s.open(p);
    if (!s) throw SceneError("cannot write " + p);
    s << header << "\n";
    s.precision(10);
    result.files_written.push_back(p);
  };
  const std::string coords = dim == 2 ? "x,y" : "x,y,z";
  const std::string tangents = dim == 2 ? "friction_stress" : "friction_stress_1,friction_stress_2";
  if (write) {
    fs::create_directories(dir);
    open(steps_csv, "steps.csv",
         "step,time,newton_iterations,jacobian_evaluations,residual_evaluations,seconds,kinetic_energy,"
         "strain_energy,external_work,normal_contact_work,friction_dissipation,energy_balance_error,"
         "normal_force_sum,friction_force_sum,max_penetration,active_nodes,equilibrium_residual,"
         "complementarity_residual,friction_residual,force_accuracy,displacement_accuracy");
    open(stress_csv, "contact_stress.csv",
         "time,node," + coords + ",normal_stress," + tangents + ",gap,normal_force");
    if (marked >= 0) open(history_csv, "node_history.csv", "time,normal_stress,friction_stress");
    // The mesh once, for plotting: nodes with the number of fixed components and the
    // contact flag (a node of Gamma_c that keeps a free dof), and the connectivity.
    std::ofstream nodes_csv, elements_csv;
    open(nodes_csv, "mesh_nodes.csv", "node," + coords + ",fixed_components,contact");
    std::vector<char> is_contact(static_cast<size_t>(M.NumNodes()), 0);
    for (const ContactNode& c : frames.nodes) is_contact[static_cast<size_t>(c.node)] = 1;
    for (int i = 0; i < M.NumNodes(); ++i) {
      int fixed = 0;
      for (int a = 0; a < dim; ++a) fixed += dofs.IsConstrained(dim * i + a) ? 1 : 0;
      nodes_csv << i;
      for (int a = 0; a < dim; ++a) nodes_csv << ',' << M.nodes(a, i);
      nodes_csv << ',' << fixed << ',' << int(is_contact[static_cast<size_t>(i)]) << '\n';
    }
    std::string element_header = "element,type";
    for (int a = 0; a < M.elements.rows(); ++a) element_header += ",n" + std::to_string(a);
    open(elements_csv, "mesh_elements.csv", element_header);
    for (int e = 0; e < M.NumElements(); ++e) {
      elements_csv << e << ',' << ToString(M.element_type);
      for (int a = 0; a < M.elements.rows(); ++a) elements_csv << ',' << M.elements(a, e);
      elements_csv << '\n';
    }
    open(displacement_csv, "displacement.csv", dim == 2 ? "time,node,ux,uy" : "time,node,ux,uy,uz");
  }
  // Full displacement of every node [m] at a stress time or the end.
  auto write_displacement = [&](double time, const Eigen::VectorXd& u_free) {
    const Eigen::VectorXd u_full = dofs.Expand(u_free);
    for (int i = 0; i < M.NumNodes(); ++i) {
      displacement_csv << time << ',' << i;
      for (int a = 0; a < dim; ++a) displacement_csv << ',' << u_full(dim * i + a);
      displacement_csv << '\n';
    }
  };
  const double dt = options.dt;
  std::vector<double> pending = scene.stress_times;
  std::sort(pending.begin(), pending.end());
  auto snapshot = [&](const std::string& name, const Eigen::VectorXd& u_free) {
    const std::string p = (dir / name).string();
    WriteVtk(p, M, {NodalVectorField("displacement", M, dofs.Expand(u_free))});
    result.files_written.push_back(p);
  };
  if (write) snapshot("snapshot_00000.vtk", Eigen::VectorXd::Zero(dofs.NumFreeDofs()));

  options.on_step = [&](const StepRecord& r, const Eigen::VectorXd& u, const ContactSystem::Result& c,
                        double force_scale) {
    if (!write) return;
    steps_csv << r.step << ',' << r.time << ',' << r.newton_iterations << ',' << r.jacobian_evaluations << ','
              << r.residual_evaluations << ',' << r.seconds << ',' << r.kinetic << ',' << r.strain << ','
              << r.external_work << ',' << r.normal_contact_work << ',' << r.friction_dissipation << ','
              << r.energy_balance_error << ',' << r.normal_force_sum << ',' << r.tangent_force_sum << ','
              << r.max_penetration << ',' << r.active_nodes << ',' << r.equilibrium_residual << ','
              << r.complementarity_residual << ',' << r.friction_residual << ',' << r.force_accuracy << ','
              << r.displacement_accuracy << '\n';
    auto stress_of = [&](size_t k) {
      const double area = frames.nodes[k].area;
      return std::pair<double, Eigen::VectorXd>(force_scale * c.normal_force(static_cast<Eigen::Index>(k)) / area,
                                                force_scale * c.tangent_force.col(static_cast<Eigen::Index>(k)) / area);
    };
    if (marked >= 0) {
      const auto [p, tau] = stress_of(static_cast<size_t>(marked));
      history_csv << r.time << ',' << p << ',' << (dim == 2 ? tau(0) : tau.norm()) << '\n';
    }
    const bool last = r.time >= options.end_time - 1e-9 * dt;
    bool at_time = false;
    while (!pending.empty() && r.time >= pending.front() - 0.5 * dt) {
      pending.erase(pending.begin());
      at_time = true;
    }
    if (at_time || last) {
      write_displacement(r.time, u);
      for (size_t k = 0; k < frames.nodes.size(); ++k) {
        const auto [p, tau] = stress_of(k);
        stress_csv << r.time << ',' << frames.nodes[k].node;
        for (int a = 0; a < dim; ++a) stress_csv << ',' << M.nodes(a, frames.nodes[k].node);
        stress_csv << ',' << p;
        for (Eigen::Index a = 0; a < tau.size(); ++a) stress_csv << ',' << tau(a);
        stress_csv << ',' << c.gap(static_cast<Eigen::Index>(k)) << ','
                   << force_scale * c.normal_force(static_cast<Eigen::Index>(k)) << '\n';
      }
    }
    if ((scene.snapshot_every > 0 && r.step % scene.snapshot_every == 0) || last) {
      char name[64];
      std::snprintf(name, sizeof name, "snapshot_%05d.vtk", r.step);
      snapshot(name, u);
    }
  };
  result.summary = NamingTheScene(scene, [&] { return RunDynamics(built.model, options); });
  return result;
}

}  // namespace contact
