// Scenes with several bodies (contact/bodies_scene.hpp): reading the [[bodies]] and
// [[contact]] tables, the static or dynamic run, and the output files.
#include "scene/scene_bodies.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <toml.hpp>
#include <tuple>

#include "contact/bodies.hpp"
#include "contact/bodies_contact.hpp"
#include "contact/bodies_scene.hpp"
#include "contact/gmsh_reader.hpp"
#include "contact/mesh_generation.hpp"
#include "contact/mortar.hpp"
#include "contact/vtk_writer.hpp"

namespace contact {
namespace {

namespace fs = std::filesystem;
using internal::Range;
using internal::Table;

const Range kVelocity{-1e9, 1e9, "m/s"};
const Range kDisplacement{-1e9, 1e9, "m"};
const Range kTime{1e-15, 1e9, "s", true};
const Range kTolerance{1e-16, 1e-2, ""};
const Range kDistance{0.0, 1e9, "m"};

/// Everything a run needs, read from the file.
struct BodiesScene {
  std::string path;
  std::vector<Body> bodies;
  std::vector<Vector> load, velocity;  // per body, its own dofs [N], its velocity [m/s]
  std::vector<MortarInterface> interfaces;
  std::vector<std::string> pair_names;
  bool dynamic = false, lumped = false;
  double dt = 0.0, end_time = 0.0, tolerance = 1e-10;
  int snapshot_every = 0;
  std::string output_directory;  // [output] directory, resolved; "" = none
};

toml::value ParseFile(const std::string& path) { return internal::ParseSceneFile(path); }

Mesh BodyMesh(const Scene& s) {
  return !s.msh_file.empty() ? ReadGmshMesh(s.msh_file)
         : s.rectangle       ? MakeRectangleMesh(*s.rectangle)
                             : MakeBoxMesh(*s.box);
}

/// One [[bodies]] table: the body, its load and its initial velocity.
void ReadBody(const Table& t, const fs::path& base, BodiesScene* out, bool* lumped) {
  Scene s;
  s.source = out->path;
  const std::string name = t.String("name");
  internal::ReadBodyTables(t, base.string(), &s);
  if (s.dim != 2)
    t.Fail("geometry",
           "is 3D: several bodies are supported in 2D only (3D mortar "
           "contact is not implemented)");
  if (s.load_history != LoadHistory::kConstant)
    t.Fail("loads", "history must be 'constant' in a scene with several bodies");
  *lumped = s.mass == MassKind::kLumped;
  ElasticBody body(BodyMesh(s), s.material, s.plane);
  std::vector<DirichletCondition> dirichlet;
  if (body.mesh().HasBoundaryGroup(kFixedGroup)) {
    DirichletCondition fixed;
    fixed.components = s.fixed_components;
    if (t.Has("fixed_displacement")) {
      const Eigen::VectorXd d = t.Vec("fixed_displacement", kDisplacement, 2);
      fixed.displacement = [d](const Eigen::VectorXd&) { return d; };
    }
    dirichlet.push_back(fixed);
  } else if (t.Has("fixed_displacement")) {
    t.Fail("fixed_displacement", "needs a 'fixed' group in the body's geometry");
  }
  Vector load = body.BodyForceLoad(s.body_force);
  if (s.traction.size() > 0) load += body.TractionLoad(s.traction, kLoadGroup);
  out->velocity.push_back(t.Has("velocity") ? t.Vec("velocity", kVelocity, 2)
                                            : Eigen::VectorXd::Zero(2));
  out->load.push_back(load);
  out->bodies.push_back({name, std::move(body), dirichlet});
  t.RejectUnknownKeys();
}

/// One [[contact]] table: a slave surface against a master surface.
void ReadPair(const Table& t, BodiesScene* out) {
  MortarInterface in;
  const std::string slave = t.String("slave_body"), master = t.String("master_body");
  in.slave_group = t.String("slave_group", kContactGroup);
  in.master_group = t.String("master_group", kContactGroup);
  in.search_distance = t.Number("search_distance", kDistance, 0.0);
  in.friction = t.Number("friction", Range{0.0, 1e3, ""}, 0.0);  // Coulomb mu
  for (const auto& [key, name, index] :
       {std::tuple<const char*, std::string, int*>{"slave_body", slave, &in.slave_body},
        {"master_body", master, &in.master_body}}) {
    try {
      *index = FindBody(out->bodies, name);
    } catch (const std::invalid_argument& e) {
      t.Fail(key, std::string(": ") + e.what() +
                      " (rigid obstacles are not supported with several bodies yet)");
    }
  }
  out->interfaces.push_back(in);
  out->pair_names.push_back(slave + "/" + in.slave_group + " -> " + master + "/" +
                            in.master_group);
  t.RejectUnknownKeys();
}

BodiesScene ReadScene(const std::string& path) {
  const toml::value root = ParseFile(path);
  const Table top(&root, "", path);
  BodiesScene scene;
  scene.path = path;
  top.String("name", fs::path(path).stem().string());
  const fs::path base = fs::path(path).parent_path();
  const toml::value& bodies = top.Get("bodies");
  if (!bodies.is_array() || bodies.as_array().empty())
    top.Fail("bodies", "must be a non-empty array of tables [[bodies]]", &bodies);
  std::vector<bool> lumped;
  for (size_t b = 0; b < bodies.as_array().size(); ++b) {
    const toml::value& v = bodies.as_array()[b];
    const std::string key = "bodies[" + std::to_string(b) + "]";
    if (!v.is_table()) top.Fail(key, "must be a table", &v);
    bool body_lumped = false;
    ReadBody(Table(&v, key, path), base, &scene, &body_lumped);
    lumped.push_back(body_lumped);
  }
  if (std::find(lumped.begin(), lumped.end(), !lumped.front()) != lumped.end())
    top.Fail("bodies",
             "mix 'material.mass' = lumped and consistent; give all bodies one");
  scene.lumped = lumped.front();
  const toml::value& pairs = top.Get("contact");
  if (!pairs.is_array() || pairs.as_array().empty())
    top.Fail("contact", "must be a non-empty array of tables [[contact]]", &pairs);
  for (size_t i = 0; i < pairs.as_array().size(); ++i) {
    const toml::value& v = pairs.as_array()[i];
    const std::string key = "contact[" + std::to_string(i) + "]";
    if (!v.is_table()) top.Fail(key, "must be a table", &v);
    ReadPair(Table(&v, key, path), &scene);
  }
  scene.dynamic = top.Choice("analysis", {"static", "dynamic"}, "static") == "dynamic";
  const Table time = top.Sub("time", scene.dynamic);
  if (scene.dynamic) {
    scene.dt = time.Number("dt", kTime);
    scene.end_time = time.Number("end_time", kTime);
    if (scene.end_time / scene.dt > kMaxTimeSteps)
      time.Fail("end_time", "/ dt = " + internal::Str(scene.end_time / scene.dt) +
                                " steps; at most " + internal::Str(kMaxTimeSteps));
  }
  time.RejectUnknownKeys();
  const Table solver = top.Sub("solver", false);
  if (solver.present()) scene.tolerance = solver.Number("tolerance", kTolerance, 1e-10);
  solver.RejectUnknownKeys();
  const Table output = top.Sub("output", false);
  if (output.present()) {
    scene.snapshot_every =
        output.Integer("snapshot_every", Range{0, kMaxTimeSteps, ""}, 0);
    if (output.Has("directory")) {
      const fs::path d = output.String("directory");
      scene.output_directory =
          (d.is_relative() ? base / d : d).lexically_normal().string();
    }
  }
  output.RejectUnknownKeys();
  top.RejectUnknownKeys();
  return scene;
}

/// The global vector of per-body vectors.
Vector Stack(const BodySystem& system, const std::vector<Vector>& parts) {
  Vector global(system.NumDofs());
  for (int b = 0; b < system.NumBodies(); ++b)
    global.segment(system.offset[static_cast<size_t>(b)],
                   parts[static_cast<size_t>(b)].size()) = parts[static_cast<size_t>(b)];
  return global;
}

/// Writes one .vtu per body for a snapshot and returns their file names.
std::vector<std::string> WriteSnapshot(const std::string& directory, int index,
                                       const BodiesScene& scene, const BodySystem& system,
                                       const MortarConstraints& constraints,
                                       const Vector& u, const Vector& contact_force,
                                       const Vector& normal_force) {
  std::vector<std::string> files;
  for (int b = 0; b < system.NumBodies(); ++b) {
    const Body& body = scene.bodies[static_cast<size_t>(b)];
    const Mesh& mesh = body.body.mesh();
    Eigen::MatrixXd pressure = Eigen::MatrixXd::Zero(1, mesh.NumNodes());
    for (int j = 0; j < constraints.NumConstraints(); ++j)
      if (constraints.slave_body[static_cast<size_t>(j)] == b)
        pressure(0, constraints.slave_node[static_cast<size_t>(j)]) =
            normal_force(j) / constraints.weight(j);
    const std::string name = body.name + "_" + std::to_string(index) + ".vtu";
    WriteVtu((fs::path(directory) / name).string(), mesh,
             {NodalVectorField("displacement", mesh, system.BodyPart(u, b)),
              NodalVectorField("contact_force", mesh, system.BodyPart(contact_force, b)),
              PointField{"contact_pressure", pressure}});
    files.push_back(name);
  }
  return files;
}

void WritePairs(const std::string& directory, const BodiesScene& scene,
                const MortarConstraints& constraints, const Vector& u,
                const Vector& normal_force) {
  std::ofstream out(fs::path(directory) / "pairs.csv");
  out << "pair,body,node,x,y,gap,force,pressure\n";
  out.precision(17);
  const Vector gap = constraints.initial_gap + constraints.B * u;
  for (int j = 0; j < constraints.NumConstraints(); ++j) {
    const Body& body =
        scene.bodies[static_cast<size_t>(constraints.slave_body[static_cast<size_t>(j)])];
    const int node = constraints.slave_node[static_cast<size_t>(j)];
    out << constraints.interface[static_cast<size_t>(j)] << "," << body.name << ","
        << node << "," << body.body.mesh().nodes(0, node) << ","
        << body.body.mesh().nodes(1, node) << "," << gap(j) << "," << normal_force(j)
        << "," << normal_force(j) / constraints.weight(j) << "\n";
  }
  if (!out) throw std::runtime_error("cannot write " + directory + "/pairs.csv");
}

/// A ParaView collection with one part per body: series holds (time [s], file) with the
/// bodies' files of each snapshot in body order.
void WriteBodiesPvd(const std::string& path,
                    const std::vector<std::pair<double, std::string>>& series,
                    int num_bodies) {
  std::ofstream out(path);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
         "  <Collection>\n";
  out.precision(17);
  for (size_t k = 0; k < series.size(); ++k)
    out << "    <DataSet timestep=\"" << series[k].first << "\" part=\""
        << k % static_cast<size_t>(num_bodies) << "\" file=\"" << series[k].second
        << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  if (!out) throw std::runtime_error("cannot write " + path);
}

/// steps.csv: per step the time [s], the normal and the friction force of each pair [N],
/// the energy [J] and the Newton iterations.
void WriteSteps(const std::string& directory, size_t pairs,
                const std::vector<BodiesStepRecord>& records) {
  std::ofstream steps(fs::path(directory) / "steps.csv");
  steps << "time";
  for (size_t i = 0; i < pairs; ++i) steps << ",pair" << i << "_force";
  for (size_t i = 0; i < pairs; ++i) steps << ",pair" << i << "_friction";
  steps << ",energy,newton_iterations\n";
  steps.precision(17);
  for (const BodiesStepRecord& record : records) {
    steps << record.time;
    for (double force : record.interface_force) steps << "," << force;
    for (double force : record.interface_tangential_force) steps << "," << force;
    steps << "," << record.energy << "," << record.newton_iterations << "\n";
  }
  if (!steps) throw std::runtime_error("cannot write " + directory + "/steps.csv");
}

std::vector<double> PairForces(const MortarConstraints& constraints, const Vector& force,
                               size_t pairs) {
  std::vector<double> sum(pairs, 0.0);
  for (int j = 0; j < constraints.NumConstraints(); ++j)
    sum[static_cast<size_t>(constraints.interface[static_cast<size_t>(j)])] += force(j);
  return sum;
}

}  // namespace

bool IsBodiesScene(const std::string& path) {
  const toml::value root = ParseFile(path);
  return root.is_table() && root.as_table().count("bodies") > 0;
}

BodiesSceneSummary RunBodiesScene(const std::string& path,
                                  const std::optional<std::string>& output_override) {
  const BodiesScene scene = ReadScene(path);
  const std::string output_directory = output_override.value_or(scene.output_directory);
  const BodySystem system = AssembleBodies(scene.bodies);
  MortarConstraints constraints;
  try {
    constraints = AssembleMortar(scene.bodies, system, scene.interfaces);
  } catch (const std::invalid_argument& e) {
    throw SceneError(path + ": " + e.what());
  }
  const Vector f = Stack(system, scene.load);
  BodiesSceneSummary summary;
  summary.constraints = constraints.NumConstraints();
  summary.pair_names = scene.pair_names;
  ncp::Options ncp = ContactNcpOptions();
  ncp.tolerance = scene.tolerance;
  const bool write = !output_directory.empty();
  if (write) fs::create_directories(output_directory);
  std::vector<std::pair<double, std::string>> series;
  Vector u, normal_force;
  if (!scene.dynamic) {
    summary.analysis = "static";
    const BodiesStaticResult r = SolveBodiesStatic(system, constraints, f, ncp);
    summary.status = r.converged ? "completed" : "solver-failure";
    summary.message = r.message;
    summary.newton_iterations = r.newton_iterations;
    summary.max_penetration = std::max(0.0, -r.gap.minCoeff());
    u = r.u;
    normal_force = r.normal_force;
    if (write)
      for (const std::string& file :
           WriteSnapshot(output_directory, 0, scene, system, constraints, u,
                         constraints.B.transpose() * normal_force, normal_force))
        series.emplace_back(0.0, file);
  } else {
    summary.analysis = "dynamic";
    BodiesDynamicOptions options;
    options.time_step = scene.dt;
    options.steps = static_cast<int>(std::lround(scene.end_time / scene.dt));
    options.lumped_mass = scene.lumped;
    options.ncp = ncp;
    Vector v0 = Vector::Zero(system.NumDofs());
    for (int b = 0; b < system.NumBodies(); ++b)
      for (int dof = 0; dof < scene.bodies[static_cast<size_t>(b)].body.NumDofs(); ++dof)
        v0(system.offset[static_cast<size_t>(b)] + dof) =
            scene.velocity[static_cast<size_t>(b)](dof % 2);
    normal_force = Vector::Zero(constraints.NumConstraints());
    options.on_step = [&](int step, const Vector& u_step, const Vector& lambda) {
      normal_force = lambda;
      if (!write || scene.snapshot_every <= 0 || step % scene.snapshot_every != 0) return;
      for (const std::string& file :
           WriteSnapshot(output_directory, step, scene, system, constraints, u_step,
                         constraints.B.transpose() * lambda, lambda))
        series.emplace_back(step * scene.dt, file);
    };
    const BodiesDynamicSummary r = RunBodiesDynamics(
        system, constraints, f, Vector::Zero(system.NumDofs()), v0, options);
    summary.status = ToString(r.status);
    summary.message = r.message;
    summary.steps = static_cast<int>(r.records.size());
    for (const BodiesStepRecord& record : r.records)
      summary.newton_iterations += record.newton_iterations;
    summary.max_penetration = r.max_penetration;
    u = r.u;
    if (write) WriteSteps(output_directory, scene.interfaces.size(), r.records);
  }
  summary.pair_force = PairForces(constraints, normal_force, scene.interfaces.size());
  if (write) {
    WritePairs(output_directory, scene, constraints, u, normal_force);
    WriteBodiesPvd((fs::path(output_directory) / "solution.pvd").string(), series,
                   system.NumBodies());
  }
  return summary;
}

}  // namespace contact
