// Reading a scene file (LoadScene, contact/scene.hpp): one function per table of the
// file, each checking every value against its range and refusing unknown keys.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <toml.hpp>

#include "contact/dynamics.hpp"
#include "contact/scene.hpp"
#include "scene/scene_bodies.hpp"
#include "scene/scene_features.hpp"
#include "scene/toml_table.hpp"

namespace contact {
namespace {

namespace fs = std::filesystem;
using internal::Range;
using internal::Str;
using internal::Table;

// A scene may be written in any consistent unit system (SI, mm-tonne-s with N and MPa, a
// body scaled by 1e-3 ...): the unit shown is SI's, and each range spans the values of
// every such system by many orders of magnitude while keeping E / (rho h^2) and the step
// counts finite.
constexpr double kMaxLength = 1e9;  // coordinates and sizes of a scene
const Range kCoordinate{-kMaxLength, kMaxLength, "m"};
const Range kLength{1e-9, kMaxLength, "m"};
const Range kDirection{-1e6, 1e6, ""};    // normals and axes, normalized by the obstacle
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

Side ParseSide(const Table& t, const std::string& key, const std::string& s, int dim) {
  static const std::map<std::string, Side> sides = {
      {"xmin", Side::kXMin}, {"xmax", Side::kXMax}, {"ymin", Side::kYMin},
      {"ymax", Side::kYMax}, {"zmin", Side::kZMin}, {"zmax", Side::kZMax}};
  const auto it = sides.find(s);
  if (it == sides.end() || (dim == 2 && (s == "zmin" || s == "zmax")))
    t.Fail(key, "has an unknown side \"" + s + "\" (xmin, xmax, ymin, ymax" +
                    (dim == 3 ? ", zmin, zmax)" : ")"));
  return it->second;
}

ElementType ParseElement(const Table& t, int dim) {
  static const std::map<std::string, ElementType> kinds = {
      {"quad4", ElementType::kQuadrilateral4}, {"tri3", ElementType::kTriangle3},
      {"hex8", ElementType::kHexahedron8},     {"tet4", ElementType::kTetrahedron4},
      {"tri6", ElementType::kTriangle6},       {"quad8", ElementType::kQuadrilateral8},
      {"quad9", ElementType::kQuadrilateral9}, {"tet10", ElementType::kTetrahedron10},
      {"hex20", ElementType::kHexahedron20},   {"hex27", ElementType::kHexahedron27}};
  const std::string e =
      dim == 2 ? t.Choice("element", {"quad4", "tri3", "tri6", "quad8", "quad9"}, "quad4")
               : t.Choice("element", {"hex8", "tet4", "tet10", "hex20", "hex27"}, "hex8");
  return kinds.at(e);
}

// geometry.file: a relative path is taken from the scene file's directory; the message of
// a missing file shows the path it resolved to.
std::string ResolveMeshFile(const Table& g, const fs::path& base) {
  const std::string given = g.String("file");
  fs::path p(given);
  if (p.is_relative()) p = base / p;
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (!fs::exists(resolved, ec))
    g.Fail("file",
           "= \"" + given + "\": no such file (resolved to " + resolved.string() +
               "; a relative path is taken from the scene file's directory)",
           &g.Get("file"));
  return resolved.string();
}

void ReadGeometry(const Table& g, const fs::path& base, Scene* s) {
  const std::string type = g.Choice("type", {"rectangle", "box", "msh"});
  if (type == "msh") {
    s->msh_file = ResolveMeshFile(g, base);
    s->dim = g.Integer("dimension", Range{2, 3, ""}, 0);
    if (s->dim != 2 && s->dim != 3)
      g.Fail("dimension", "must be 2 or 3 for a .msh geometry");
    internal::ReadGroupNames(g, s);
  } else {
    s->dim = type == "rectangle" ? 2 : 3;
    std::map<Side, BoundaryRole> roles;
    const std::pair<const char*, BoundaryRole> role_keys[] = {
        {"fixed", BoundaryRole::kFixed},
        {"load", BoundaryRole::kLoad},
        {"contact", BoundaryRole::kContact}};
    for (const auto& [key, role] : role_keys)
      for (const std::string& side : g.Strings(key)) {
        const Side sd = ParseSide(g, key, side, s->dim);
        if (roles.count(sd)) g.Fail(key, "assigns side " + side + " a second role");
        roles[sd] = role;
      }
    const Eigen::VectorXd origin = g.Has("origin") ? g.Vec("origin", kCoordinate, s->dim)
                                                   : Eigen::VectorXd::Zero(s->dim);
    const Eigen::VectorXd size = g.Vec("size", kLength, s->dim);
    const std::vector<double> cells =
        g.Numbers("cells", Range{1, kMaxGeneratedCells, ""}, s->dim);
    for (double c : cells)
      if (c != std::floor(c))
        g.Fail("cells", "entries must be integers, got " + Str(c), &g.Get("cells"));
    const std::string grid_error =
        CheckGridLimits(std::vector<double>(size.data(), size.data() + s->dim), cells);
    if (!grid_error.empty())
      g.Fail("size", "and 'cells': " + grid_error, &g.Get("cells"));
    const bool structured = g.Choice("topology", {"structured", "unstructured"},
                                     "structured") == "structured";
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
  for (double c : g.Has("fixed_components")
                      ? g.Numbers("fixed_components", Range{0, 2, ""})
                      : std::vector<double>{}) {
    if (c != std::floor(c) || c < 0 || c >= s->dim)
      g.Fail("fixed_components",
             "entries must be components 0.." + std::to_string(s->dim - 1));
    s->fixed_components.push_back(static_cast<int>(c));
  }
  s->fixed_displacement = internal::ReadHistory(g, "fixed_displacement", s->dim);
  g.RejectUnknownKeys();
}

/// obstacle.normal of a plane: a unit vector, |n| = 1 within kUnitNormalSlack. Not
/// normalized silently: a normal [0, 2] would change what offset means (n . y <= offset).
Eigen::VectorXd PlaneNormal(const Table& o, int dim) {
  constexpr double kUnitNormalSlack = 1e-3;
  const Eigen::VectorXd n = o.Vec("normal", kDirection, dim);
  const double length = n.norm();
  if (!(std::abs(length - 1.0) <= kUnitNormalSlack))
    o.Fail("normal",
           "must be a unit vector (|n| = 1 within " + Str(kUnitNormalSlack) +
               "), got |n| = " + Str(length) +
               ": divide it by its length (and offset alike)",
           &o.Get("normal"));
  return n;
}

std::shared_ptr<RigidObstacle> ReadObstacle(const Table& o, int dim) {
  const std::string type = o.Choice("type", {"plane", "parabola", "sphere", "cylinder"});
  std::shared_ptr<RigidObstacle> obstacle;
  try {
    if (type == "plane") {
      // The obstacle fills {y : n . y <= offset}; the body lies where n . x >= offset.
      obstacle = std::make_shared<HalfSpace>(PlaneNormal(o, dim),
                                             o.Number("offset", kCoordinate));
    } else if (type == "parabola") {
      obstacle = std::make_shared<ParabolaObstacle>(dim, o.Number("vertex", kCoordinate),
                                                    o.Number("coefficient", kCurvature));
    } else if (type == "sphere") {
      obstacle = std::make_shared<SphereObstacle>(o.Vec("center", kCoordinate, dim),
                                                  o.Number("radius", kLength));
    } else {
      if (dim != 3) o.Fail("type", "\"cylinder\" needs a 3D geometry");
      obstacle = std::make_shared<CylinderObstacle>(
          o.Vec("axis_point", kCoordinate, 3), o.Vec("axis_direction", kDirection, 3),
          o.Number("radius", kLength));
    }
  } catch (const SceneError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    o.Fail("type", std::string("= \"") + type + "\": " + e.what());
  }
  return obstacle;
}

/// The deepest nesting of arrays and inline tables in TOML text, with the line where it
/// is reached; strings and comments are skipped. toml11 parses nested values recursively,
/// so a few hundred thousand '[' overflow the stack: this runs before it.
std::pair<int, int> MaxNestingDepth(const std::string& text) {
  int depth = 0, deepest = 0, line = 1, deepest_line = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const std::string quote = text.compare(i, 3, std::string(3, c)) == 0
                                    ? std::string(3, c)
                                    : std::string(1, c);
      for (i += quote.size();
           i < text.size() && text.compare(i, quote.size(), quote) != 0; ++i) {
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
  if (ec || !fs::exists(status))
    throw SceneError(path + ": cannot read scene file: no such file");
  if (!fs::is_regular_file(status))
    throw SceneError(path +
                     ": cannot read scene file: not a regular file (a directory?)");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > kMaxSceneFileBytes)
    throw SceneError(path + ": scene file of " + std::to_string(bytes) +
                     " bytes; at most " + std::to_string(kMaxSceneFileBytes) +
                     " bytes are accepted");
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)),
                   std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw SceneError(path + ": cannot read scene file");
  const auto [depth, line] = MaxNestingDepth(text);
  if (depth > kMaxSceneNesting)
    throw SceneError(path + ":" + std::to_string(line) +
                     ": arrays or inline tables nested " + std::to_string(depth) +
                     " deep; at most " + std::to_string(kMaxSceneNesting) +
                     " levels are accepted");
  return text;
}

/// Parses the scene text and applies the overrides: each "table.key" = TOML literal
/// replaces the file's value before validation, so it is checked (and named in messages,
/// at "command line") like a value of the file.
toml::value ParseScene(const std::string& path, const std::string& scene_text,
                       const SceneOverrides& overrides) {
  toml::value root;
  std::istringstream text(scene_text);
  try {
    root = toml::parse(text, path);
  } catch (const std::exception& e) {
    throw SceneError("cannot read scene file " + path + ": " + e.what());
  }
  for (const auto& [dotted, literal] : overrides) {
    const size_t dot = dotted.find('.');
    if (dot == std::string::npos || dotted.find('.', dot + 1) != std::string::npos)
      throw SceneError("command line: override key '" + dotted + "' must be table.key");
    std::istringstream value_text("value = " + literal);
    toml::value parsed;
    try {
      parsed = toml::parse(value_text, "command line (" + dotted + ")");
    } catch (const std::exception& e) {
      throw SceneError("command line: '" + dotted + "' = " + literal +
                       " is not a TOML value: " + e.what());
    }
    toml::value& table = root.as_table()[dotted.substr(0, dot)];
    if (table.is_uninitialized()) table = toml::table{};
    if (!table.is_table())
      throw SceneError(path + ": '" + dotted.substr(0, dot) + "' must be a table");
    table.as_table()[dotted.substr(dot + 1)] = parsed.as_table().at("value");
  }
  return root;
}

/// [material] model, kinematics and kinematics_tolerance (contact/kinematics.hpp).
void ReadKinematics(const Table& m, Scene* s) {
  s->kinematics.model = MaterialModelFromString(
      m.Choice("model", {"linear", "saint-venant-kirchhoff", "neo-hookean"}, "linear"));
  s->kinematics.kinematics =
      KinematicsFromString(m.Choice("kinematics", {"auto", "small", "finite"}, "auto"));
  s->kinematics.tolerance =
      m.Number("kinematics_tolerance", Range{0.0, 1.0, "", true, false}, 1e-2);
  if (s->kinematics.kinematics == Kinematics::kSmall &&
      s->kinematics.model != MaterialModel::kLinear)
    m.Fail("model", std::string("= \"") + ToString(s->kinematics.model) +
                        "\" is a finite-strain model: it needs kinematics = \"auto\" or "
                        "\"finite\", got \"small\"");
}

/// [material]: Young's modulus, Poisson's ratio, density, mass matrix, 2D plane model.
void ReadMaterial(const Table& m, Scene* s) {
  s->material.youngs_modulus = m.Number("young_modulus", kModulus);
  s->material.poisson_ratio = m.Number("poisson_ratio", kPoisson);
  s->material.density = m.Number("density", kDensity);
  s->mass = m.Choice("mass", {"consistent", "lumped"}, "consistent") == "lumped"
                ? MassKind::kLumped
                : MassKind::kConsistent;
  if (s->dim == 2) {
    s->plane.model = m.Choice("plane", {"strain", "stress"}, "strain") == "stress"
                         ? PlaneModel::kPlaneStress
                         : PlaneModel::kPlaneStrain;
    s->plane.thickness = m.Number("thickness", kLength, 1.0);
  }
  internal::ReadDamping(m, s);
  ReadKinematics(m, s);
  m.RejectUnknownKeys();
}

/// [loads]: body force, traction on "load", and their time history.
void ReadLoads(const Table& l, Scene* s) {
  s->body_force = l.Has("body_force") ? l.Vec("body_force", kForceDensity, s->dim)
                                      : Eigen::VectorXd::Zero(s->dim);
  if (l.Has("traction")) s->traction = l.Vec("traction", kStress, s->dim);
  const std::string history =
      l.Choice("history", {"constant", "step", "ramp"}, "constant");
  s->load_history = history == "step"   ? LoadHistory::kStep
                    : history == "ramp" ? LoadHistory::kRamp
                                        : LoadHistory::kConstant;
  if (s->load_history == LoadHistory::kRamp) s->ramp_time = l.Number("ramp_time", kTime);
  l.RejectUnknownKeys();
}

/// [time]: step, end, stability override and the initial state; at most kMaxTimeSteps
/// steps.
void ReadTime(const Table& t, Scene* s) {
  s->dynamics.dt = t.Number("dt", kTime);
  s->dynamics.end_time = t.Number("end_time", kTime);
  const double steps = std::ceil(s->dynamics.end_time / s->dynamics.dt);
  if (steps > kMaxTimeSteps)
    t.Fail("dt",
           "= " + Str(s->dynamics.dt) +
               " s with time.end_time = " + Str(s->dynamics.end_time) + " s gives " +
               Str(steps) + " time steps; at most " + Str(kMaxTimeSteps) +
               " are accepted (one step record each)",
           &t.Get("dt"));
  if (s->dynamics.end_time < s->dynamics.dt)
    s->warnings.push_back("time.end_time = " + Str(s->dynamics.end_time) +
                          " s is shorter than time.dt = " + Str(s->dynamics.dt) +
                          " s: one step of dt is run, ending at t = dt");
  s->dynamics.allow_unstable_time_step = t.Boolean("allow_unstable", false);
  const std::string initial = t.Choice("initial_state", {"static", "velocity"}, "static");
  if (initial == "velocity") {
    s->dynamics.initial_state = InitialState::kPrescribed;
    s->initial_velocity = t.Vec("initial_velocity", kVelocity, s->dim);
  }
  t.RejectUnknownKeys();
}

/// Keys and values of [solver] that were renamed: an old scene file fails with a message
/// that says what to write instead.
void RejectRenamedSolverKeys(const Table& v) {
  std::string key, fixes;  // the first renamed key, and what to write for each
  const toml::value* at = nullptr;
  if (v.Has("method")) {
    const toml::value& old = v.Get("method");
    const std::string value = old.is_string() ? old.as_string().str : "";
    key = "method", at = &old;
    fixes = value == "ipopt"
                ? "= \"ipopt\" is now a step method: write solver.step = \"ipopt\""
                : "was renamed: write solver.ncp_function = \"" +
                      (value.empty() ? std::string("fb") : value) +
                      "\" (fb, min or penalized-fb; Ipopt is solver.step = \"ipopt\")";
  }
  if (v.Has("friction") && v.Get("friction").is_string() &&
      v.Get("friction").as_string().str == "eq94") {
    const std::string fix =
        "= \"eq94\" was renamed: write solver.friction = \"lagged-bound\" (Tresca "
        "with the previous step's bound f_c lambda^k, thesis eq. 94)";
    if (key.empty())
      key = "friction", at = &v.Get("friction"), fixes = fix;
    else
      fixes += "; and 'solver.friction' " + fix;
  }
  if (!key.empty()) v.Fail(key, fixes, at);
}

/// [solver]: how each step is posed and solved (step, friction), the Newton settings
/// (ncp_function, tolerance, max_iterations, linear_solver) and the checks.
void ReadSolver(const Table& v, Scene* s) {
  RejectRenamedSolverKeys(v);
  const std::string step = v.Choice(
      "step", {"auto", "condensed", "sparse", "full", "explicit", "ipopt"}, "auto");
  s->dynamics.step_method = step == "full"        ? StepMethod::kFull
                            : step == "explicit"  ? StepMethod::kExplicit
                            : step == "sparse"    ? StepMethod::kSparse
                            : step == "condensed" ? StepMethod::kCondensed
                            : step == "ipopt"     ? StepMethod::kIpopt
                                                  : StepMethod::kAuto;
  if (s->dynamics.step_method == StepMethod::kExplicit && s->mass != MassKind::kLumped)
    v.Fail("step", "= \"explicit\" needs material.mass = \"lumped\"");
  if (s->dynamics.step_method == StepMethod::kIpopt && s->friction_coefficient > 0)
    v.Fail("step",
           "= \"ipopt\" solves frictionless steps only, but friction.coefficient = " +
               std::to_string(s->friction_coefficient));
  const std::string function =
      v.Choice("ncp_function", {"fb", "min", "penalized-fb"}, "fb");
  s->dynamics.ncp.ncp_function = function == "min" ? ncp::NcpFunction::kMin
                                 : function == "penalized-fb"
                                     ? ncp::NcpFunction::kPenalizedFischerBurmeister
                                     : ncp::NcpFunction::kFischerBurmeister;
  s->dynamics.ncp.tolerance = v.Number("tolerance", kRelativeTolerance, 1e-10);
  s->dynamics.ncp.max_iterations = v.Integer("max_iterations", kIterations, 500);
  const std::string ls =
      v.Choice("linear_solver", {"auto", "dense", "sparse-lu", "umfpack", "klu"}, "auto");
  s->dynamics.ncp.linear_solver = ls == "dense"       ? ncp::LinearSolverType::kDenseLU
                                  : ls == "sparse-lu" ? ncp::LinearSolverType::kSparseLU
                                  : ls == "umfpack"   ? ncp::LinearSolverType::kUmfpack
                                  : ls == "klu"       ? ncp::LinearSolverType::kKlu
                                                      : ncp::LinearSolverType::kAuto;
  const std::string friction =
      v.Choice("friction", {"default", "lagged-bound", "coulomb-fc"}, "default");
  if (friction != "default")
    s->dynamics.friction_formulation = friction == "lagged-bound"
                                           ? FrictionFormulation::kLaggedBound
                                           : FrictionFormulation::kCoulombFc;
  const StepMethod chosen = s->dynamics.step_method;
  if (friction == "coulomb-fc" && chosen != StepMethod::kCondensed &&
      chosen != StepMethod::kSparse && chosen != StepMethod::kAuto)
    v.Fail("friction",
           "= \"coulomb-fc\" needs solver.step = \"auto\", \"condensed\" or \"sparse\", "
           "got \"" +
               step + "\"");
  if (friction == "lagged-bound" && chosen == StepMethod::kSparse)
    v.Fail(
        "friction",
        "= \"lagged-bound\" needs solver.step = \"auto\", \"condensed\" or \"full\" (the "
        "sparse step solves implicit Coulomb only), got \"sparse\"");
  s->dynamics.ncp.log_to_stderr = v.Boolean("log_iterations", false);
  s->dynamics.compare_with_ipopt = v.Boolean("compare_with_ipopt", false);
  if (s->dynamics.compare_with_ipopt && s->friction_coefficient > 0)
    v.Fail("compare_with_ipopt", "needs a frictionless scene");
  v.RejectUnknownKeys();
}

/// [output]: directory (a relative one is taken from the working directory of the run,
/// not from the scene file: an installed scene does not write into the install prefix),
/// stress times, snapshots, marked point.
void ReadOutput(const Table& out, Scene* s) {
  if (out.Has("directory"))
    s->output_directory = fs::path(out.String("directory")).lexically_normal().string();
  if (out.Has("stress_times")) s->stress_times = out.Numbers("stress_times", kTimeOrZero);
  s->snapshot_every = out.Integer("snapshot_every", Range{0, kMaxTimeSteps, ""}, 0);
  s->checkpoint_every = out.Integer("checkpoint_every", Range{0, kMaxTimeSteps, ""},
                                    kDefaultCheckpointEvery);
  if (out.Has("marked_point"))
    s->marked_point = out.Vec("marked_point", kCoordinate, s->dim);
  out.RejectUnknownKeys();
}

// Stress times after the last step are never reached: say so instead of writing nothing.
void WarnAboutStressTimes(Scene* s) {
  const double last = std::ceil(s->dynamics.end_time / s->dynamics.dt) * s->dynamics.dt;
  for (const double t : s->stress_times)
    if (t - 0.5 * s->dynamics.dt > last)
      s->warnings.push_back("output.stress_times has " + Str(t) +
                            " s, after the last step (t = " + Str(last) +
                            " s): nothing is recorded at it");
}

}  // namespace

Scene LoadScene(const std::string& path, const SceneOverrides& overrides) {
  Scene s;
  s.text = ReadSceneText(path);
  const toml::value root = ParseScene(path, s.text, overrides);
  if (!overrides.empty() && !s.text.empty() && s.text.back() != '\n') s.text += '\n';
  for (const auto& [key, literal] : overrides)
    s.text += "# override: " + key + " = " + literal + "\n";
  s.source = path;
  const fs::path base = fs::path(path).parent_path();
  const Table top(&root, "", path);
  if (top.Has("bodies"))
    throw SceneError(
        path +
        ": a scene with several bodies ([[bodies]]) runs through contact-sim "
        "or contact::RunBodiesScene (docs/several-bodies.md); LoadScene, "
        "Simulation and MPI ranks take one body");
  s.name = top.String("name", fs::path(path).stem().string());

  ReadGeometry(top.Sub("geometry", true), base, &s);
  ReadMaterial(top.Sub("material", true), &s);
  ReadLoads(top.Sub("loads", false), &s);
  const Table o = top.Sub("obstacle", true);
  s.obstacle = ReadObstacle(o, s.dim);
  s.obstacle_motion = internal::ReadHistory(o, "motion", s.dim);
  s.normal_source = o.Choice("normal_source", {"body", "obstacle"}, "body") == "obstacle"
                        ? NormalSource::kObstacle
                        : NormalSource::kBody;
  o.RejectUnknownKeys();
  const Table f = top.Sub("friction", false);
  s.friction_coefficient = f.Number("coefficient", kFriction, 0.0);
  f.RejectUnknownKeys();
  ReadTime(top.Sub("time", true), &s);
  ReadSolver(top.Sub("solver", false), &s);
  ReadOutput(top.Sub("output", false), &s);
  top.RejectUnknownKeys();
  WarnAboutStressTimes(&s);
  internal::CheckSceneFeatures(s);
  return s;
}

}  // namespace contact

namespace contact::internal {

toml::value ParseSceneFile(const std::string& path) {
  return ParseScene(path, ReadSceneText(path), {});
}

void ReadBodyTables(const Table& body, const std::string& base, Scene* s) {
  ReadGeometry(body.Sub("geometry", true), base, s);
  ReadMaterial(body.Sub("material", true), s);
  ReadLoads(body.Sub("loads", false), s);
}

}  // namespace contact::internal
