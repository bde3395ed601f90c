// The checkpoint file of contact::Simulation (checkpoint.hpp has the format).
#include "checkpoint.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "contact/simulation.hpp"
#include "ncp/output_file.hpp"

namespace contact {

CheckpointError::CheckpointError(const std::string& message)
    : std::runtime_error(message) {}

namespace internal {
namespace {

constexpr char kMagic[8] = {'N', 'C', 'P', 'C', 'K', 'P', 'T', '\n'};
constexpr std::uint32_t kByteOrderMark = 0x01020304;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8;
/// Larger files are refused before they are read (a corrupt length must not allocate).
constexpr std::uint64_t kMaxCheckpointBytes = std::uint64_t{1} << 40;  // 1 TiB

// One field list for both directions: Io is a writing or a reading visitor with
// operator() for every field type.
class Writing {
 public:
  explicit Writing(BinaryWriter* out) : out_(*out) {}
  void operator()(const char*, std::int64_t v) { out_.Int(v); }
  void operator()(const char*, int v) { out_.Int(v); }
  void operator()(const char*, std::uint64_t v) { out_.Unsigned(v); }
  void operator()(const char*, bool v) { out_.Int(v ? 1 : 0); }
  void operator()(const char*, double v) { out_.Double(v); }
  void operator()(const char*, const std::string& s) { out_.String(s); }
  void operator()(const char*, const Eigen::VectorXd& v) {
    out_.Unsigned(static_cast<std::uint64_t>(v.size()));
    out_.Raw(v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
  }
  void operator()(const char*, const Eigen::MatrixXd& m) {
    out_.Unsigned(static_cast<std::uint64_t>(m.rows()));
    out_.Unsigned(static_cast<std::uint64_t>(m.cols()));
    out_.Raw(m.data(), sizeof(double) * static_cast<std::size_t>(m.size()));
  }
  template <class Enum, class = std::enable_if_t<std::is_enum_v<Enum>>>
  void operator()(const char* what, Enum e) {
    (*this)(what, static_cast<std::int64_t>(e));
  }

 private:
  BinaryWriter& out_;
};

class Reading {
 public:
  explicit Reading(BinaryReader* in) : in_(*in) {}
  void operator()(const char* what, std::int64_t& v) { v = in_.Int(what); }
  void operator()(const char* what, int& v) {
    v = static_cast<int>(Bounded(what, -(1LL << 31), (1LL << 31) - 1));
  }
  void operator()(const char* what, std::uint64_t& v) { v = in_.Unsigned(what); }
  void operator()(const char* what, bool& v) { v = Bounded(what, 0, 1) != 0; }
  void operator()(const char* what, double& v) { v = in_.Double(what); }
  void operator()(const char* what, std::string& s) { s = in_.String(what); }
  void operator()(const char* what, Eigen::VectorXd& v) {
    v.resize(static_cast<Eigen::Index>(in_.Count(what, sizeof(double))));
    in_.Raw(v.data(), sizeof(double) * static_cast<std::size_t>(v.size()), what);
  }
  void operator()(const char* what, Eigen::MatrixXd& m) {
    const std::uint64_t rows = in_.Unsigned(what), cols = in_.Unsigned(what);
    // (Each dimension bounded too: a 0 x 2^63 matrix holds no entries but is no Eigen
    // size.)
    constexpr std::uint64_t kMaxDimension = std::uint64_t{1} << 31;
    if (rows > kMaxDimension || cols > kMaxDimension ||
        (rows != 0 && cols > in_.left() / sizeof(double) / rows))
      in_.Fail(std::string(what) + ": a " + std::to_string(rows) + " x " +
               std::to_string(cols) + " matrix does not fit into the " +
               std::to_string(in_.left()) + " bytes left");
    m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    in_.Raw(m.data(), sizeof(double) * static_cast<std::size_t>(m.size()), what);
  }
  template <class Enum, class = std::enable_if_t<std::is_enum_v<Enum>>>
  void operator()(const char* what, Enum& e) {
    e = static_cast<Enum>(Bounded(what, 0, 64));
  }

 private:
  std::int64_t Bounded(const char* what, std::int64_t low, std::int64_t high) {
    const std::int64_t v = in_.Int(what);
    if (v < low || v > high)
      in_.Fail(std::string(what) + " = " + std::to_string(v) + " is outside [" +
               std::to_string(low) + ", " + std::to_string(high) + "]");
    return v;
  }
  BinaryReader& in_;
};

// (Data is const CheckpointData for writing, CheckpointData for reading.)
template <class Io, class Record>
void RecordFields(Io& io, Record& r) {
  io("record.step", r.step);
  io("record.time", r.time);
  io("record.newton_iterations", r.newton_iterations);
  io("record.jacobian_evaluations", r.jacobian_evaluations);
  io("record.residual_evaluations", r.residual_evaluations);
  io("record.krylov_iterations", r.krylov_iterations);
  io("record.seconds", r.seconds);
  io("record.solve_seconds", r.solve_seconds);
  io("record.solver_status", r.solver_status);
  io("record.kinetic", r.kinetic);
  io("record.strain", r.strain);
  io("record.external_work", r.external_work);
  io("record.normal_contact_work", r.normal_contact_work);
  io("record.friction_dissipation", r.friction_dissipation);
  io("record.damping_dissipation", r.damping_dissipation);
  io("record.energy_balance_error", r.energy_balance_error);
  io("record.normal_force_sum", r.normal_force_sum);
  io("record.tangent_force_sum", r.tangent_force_sum);
  io("record.max_penetration", r.max_penetration);
  io("record.active_nodes", r.active_nodes);
  io("record.equilibrium_residual", r.equilibrium_residual);
  io("record.complementarity_residual", r.complementarity_residual);
  io("record.friction_residual", r.friction_residual);
  io("record.force_accuracy", r.force_accuracy);
  io("record.displacement_accuracy", r.displacement_accuracy);
  io("record.accurate", r.accurate);
  io("record.ipopt_relative_difference", r.ipopt_relative_difference);
}

template <class Io, class Summary>
void SummaryFields(Io& io, Summary& s) {
  io("summary.status", s.status);
  io("summary.message", s.message);
  io("summary.step_method", s.step_method);
  io("summary.steps", s.steps);
  io("summary.newton_iterations", s.newton_iterations);
  io("summary.jacobian_evaluations", s.jacobian_evaluations);
  io("summary.residual_evaluations", s.residual_evaluations);
  io("summary.friction_restarts", s.friction_restarts);
  io("summary.krylov_iterations", s.krylov_iterations);
  io("summary.seconds", s.seconds);
  io("summary.assembly_seconds", s.assembly_seconds);
  io("summary.mass_solve_seconds", s.mass_solve_seconds);
  io("summary.contact_solve_seconds", s.contact_solve_seconds);
  io("summary.accuracy_check_seconds", s.accuracy_check_seconds);
  io("summary.mass_solves", s.mass_solves);
  io("summary.max_penetration", s.max_penetration);
  io("summary.max_equilibrium_residual", s.max_equilibrium_residual);
  io("summary.max_complementarity_residual", s.max_complementarity_residual);
  io("summary.max_friction_residual", s.max_friction_residual);
  io("summary.inaccurate_steps", s.inaccurate_steps);
  io("summary.energy_balance_error", s.energy_balance_error);
  io("summary.critical_time_step", s.critical_time_step);
  io("summary.max_ipopt_relative_difference", s.max_ipopt_relative_difference);
  io("summary.kinematics", s.kinematics);
  io("summary.finite_strain_from_step", s.finite_strain_from_step);
  io("summary.material_model", s.material_model);
  io("summary.max_rotation", s.max_rotation);
  io("summary.max_spurious_strain", s.max_spurious_strain);
  io("summary.small_strain_invalid_step", s.small_strain_invalid_step);
  io("summary.u", s.u);
}

template <class Io, class Data>
void CheckpointFields(Io& io, Data& d) {
  auto& id = d.identity;
  io("identity.scene_source", id.scene_source);
  io("identity.scene_text", id.scene_text);
  io("identity.scene_hash", id.scene_hash);
  io("identity.mesh_file", id.mesh_file);
  io("identity.mesh_hash", id.mesh_hash);
  io("identity.model_hash", id.model_hash);
  io("identity.dim", id.dim);
  io("identity.free_dofs", id.free_dofs);
  io("identity.contact_nodes", id.contact_nodes);
  io("identity.num_steps", id.num_steps);
  io("identity.step_method", id.step_method);
  io("k", d.k);
  io("u", d.carried.u);
  io("u_previous", d.carried.u_previous);
  io("lambda", d.carried.lambda);
  io("Ku", d.carried.Ku);
  io("Mdu_previous", d.carried.Mdu_previous);
  io("du", d.carried.du);
  io("contact_force_max", d.carried.contact_force_max);
  io("contact.x", d.carried.contact.x);
  io("contact.normal_force", d.carried.contact.normal_force);
  io("contact.tangent_force", d.carried.contact.tangent_force);
  io("contact.gap", d.carried.contact.gap);
  io("contact.slip", d.carried.contact.slip);
  io("gaps", d.gaps);
  io("energy.kinetic0", d.energy.kinetic0);
  io("energy.energy0", d.energy.energy0);
  io("energy.strain0", d.energy.strain0);
  io("energy.external_work", d.energy.external_work);
  io("energy.normal_work", d.energy.normal_work);
  io("energy.friction_dissipation", d.energy.friction_dissipation);
  io("energy.damping_dissipation", d.energy.damping_dissipation);
  io("energy.work_scale", d.energy.work_scale);
  io("warm_start", d.warm_start);
  RecordFields(io, d.first_inaccurate);
  SummaryFields(io, d.summary);
  io("has_scene", d.has_scene);
  io("body_force", d.body_force);
  io("obstacle_translation", d.obstacle_translation);
  io("application_data", d.application_data);
}

void WriteRecords(BinaryWriter* out, const std::vector<StepRecord>& records) {
  Writing io(out);
  io("records", static_cast<std::uint64_t>(records.size()));
  for (const StepRecord& r : records) RecordFields(io, r);
}

void ReadRecords(BinaryReader* in, std::vector<StepRecord>* records) {
  Reading io(in);
  // A record takes at least 8 bytes per field: a bound on the count before reserving.
  const std::uint64_t n = in->Count("records", 25 * 8);
  records->clear();
  records->reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) RecordFields(io, records->emplace_back());
}

template <class T>
void HashBytes(const T* p, std::size_t n, std::uint64_t* hash) {
  *hash = Fnv1a(std::string_view(reinterpret_cast<const char*>(p), n * sizeof(T)), *hash);
}

void HashSparse(const Eigen::SparseMatrix<double>& A, std::uint64_t* hash) {
  const Eigen::Index dims[2] = {A.rows(), A.cols()};
  HashBytes(dims, 2, hash);
  HashBytes(A.outerIndexPtr(), static_cast<std::size_t>(A.outerSize()) + 1, hash);
  if (!A.isCompressed()) {
    HashBytes(A.innerNonZeroPtr(), static_cast<std::size_t>(A.outerSize()), hash);
  }
  HashBytes(A.innerIndexPtr(), static_cast<std::size_t>(A.nonZeros()), hash);
  HashBytes(A.valuePtr(), static_cast<std::size_t>(A.nonZeros()), hash);
}

}  // namespace

std::uint64_t Fnv1a(std::string_view bytes, std::uint64_t hash) {
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::uint64_t ModelFingerprint(const DynamicModel& model, const DynamicOptions& options) {
  std::uint64_t hash = Fnv1a("contact model");
  HashBytes(&model.dim, 1, &hash);
  HashSparse(model.K, &hash);
  HashSparse(model.M, &hash);
  for (const ContactNode& c : model.contact_nodes) {
    HashBytes(&c.node, 1, &hash);
    HashBytes(c.dofs, 3, &hash);
    for (const Eigen::Vector3d* v : {&c.normal, &c.tangent1, &c.tangent2})
      HashBytes(v->data(), 3, &hash);
    HashBytes(&c.gap, 1, &hash);
    HashBytes(&c.area, 1, &hash);
  }
  const double numbers[] = {options.dt, options.start_time, options.end_time,
                            options.friction_coefficient, options.ncp.tolerance};
  HashBytes(numbers, std::size(numbers), &hash);
  const double damping[] = {model.damping.mass, model.damping.stiffness};
  HashBytes(damping, std::size(damping), &hash);
  const int choices[] = {static_cast<int>(options.step_method),
                         static_cast<int>(options.friction_formulation),
                         static_cast<int>(options.initial_state),
                         static_cast<int>(options.ncp.ncp_function)};
  HashBytes(choices, std::size(choices), &hash);
  if (model.kinematics) {  // (small strain without a kinematics object: as before)
    const KinematicsOptions& k = model.kinematics->options();
    const int kinematics[] = {static_cast<int>(k.kinematics), static_cast<int>(k.model)};
    HashBytes(kinematics, std::size(kinematics), &hash);
    HashBytes(&k.tolerance, 1, &hash);
  }
  return hash;
}

void WriteCheckpoint(const std::string& path, const CheckpointData& data) {
  BinaryWriter payload;
  Writing io(&payload);
  CheckpointFields(io, data);
  WriteRecords(&payload, data.summary.records);
  BinaryWriter header;
  header.Raw(kMagic, sizeof kMagic);
  const std::uint32_t version = kCheckpointVersion, mark = kByteOrderMark;
  header.Raw(&version, sizeof version);
  header.Raw(&mark, sizeof mark);
  header.Unsigned(payload.bytes().size());
  ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path);
  file.Write(header.bytes());
  file.Write(payload.bytes());
  const std::uint64_t checksum = Fnv1a(payload.bytes());
  file.Write(std::string_view(reinterpret_cast<const char*>(&checksum), sizeof checksum));
  file.Close();
}

CheckpointData ParseCheckpoint(std::string_view bytes, const std::string& name) {
  BinaryReader header(bytes, name);
  char magic[sizeof kMagic];
  if (bytes.size() < sizeof kMagic ||
      std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    header.Fail("not a contact checkpoint (the file does not start with \"NCPCKPT\")");
  if (bytes.size() < kHeaderBytes + 8)
    header.Fail("truncated: " + std::to_string(bytes.size()) +
                " bytes, a checkpoint has at least " + std::to_string(kHeaderBytes + 8));
  header.Raw(magic, sizeof magic, "magic");
  std::uint32_t version = 0, mark = 0;
  header.Raw(&version, sizeof version, "format version");
  if (version != kCheckpointVersion)
    header.Fail("format version " + std::to_string(version) +
                ", this build reads version " + std::to_string(kCheckpointVersion));
  header.Raw(&mark, sizeof mark, "byte-order mark");
  if (mark != kByteOrderMark) header.Fail("written on a machine of the other byte order");
  const std::uint64_t length = header.Unsigned("payload length");
  if (length != bytes.size() - (kHeaderBytes + 8))
    header.Fail("truncated or extended: the header announces " + std::to_string(length) +
                " bytes of state, the file has " + std::to_string(bytes.size()) +
                " bytes in all (expected " + std::to_string(length + kHeaderBytes + 8) +
                ")");
  const std::string_view payload = bytes.substr(kHeaderBytes, length);
  std::uint64_t checksum = 0;
  std::memcpy(&checksum, bytes.data() + kHeaderBytes + length, sizeof checksum);
  if (checksum != Fnv1a(payload))
    header.Fail("corrupt: the checksum of the state does not match");
  CheckpointData data;
  BinaryReader in(payload, name);
  Reading io(&in);
  CheckpointFields(io, data);
  ReadRecords(&in, &data.summary.records);
  if (in.left() != 0) in.Fail(std::to_string(in.left()) + " bytes after the last field");
  return data;
}

CheckpointData ReadCheckpoint(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file)
    throw CheckpointError("cannot read checkpoint '" + path +
                          "': " + std::strerror(errno));
  file.seekg(0, std::ios::end);
  const std::streamoff size = file.tellg();
  if (size < 0 || static_cast<std::uint64_t>(size) > kMaxCheckpointBytes)
    throw CheckpointError("checkpoint '" + path +
                          "': not a regular file of at most 1 TiB");
  file.seekg(0);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!file.read(bytes.data(), size))
    throw CheckpointError("cannot read checkpoint '" + path +
                          "': " + std::strerror(errno));
  return ParseCheckpoint(bytes, path);
}

std::int64_t BinaryReader::Int(const char* what) {
  std::int64_t v;
  Raw(&v, sizeof v, what);
  return v;
}

std::uint64_t BinaryReader::Unsigned(const char* what) {
  std::uint64_t v;
  Raw(&v, sizeof v, what);
  return v;
}

double BinaryReader::Double(const char* what) {
  double v;
  Raw(&v, sizeof v, what);
  return v;
}

std::string BinaryReader::String(const char* what) {
  std::string s(Count(what, 1), '\0');
  Raw(s.data(), s.size(), what);
  return s;
}

std::uint64_t BinaryReader::Count(const char* what, std::size_t element_bytes) {
  const std::uint64_t n = Unsigned(what);
  if (n > left() / element_bytes)
    Fail(std::string(what) + ": " + std::to_string(n) + " elements do not fit into the " +
         std::to_string(left()) + " bytes left");
  return n;
}

void BinaryReader::Raw(void* p, std::size_t n, const char* what) {
  if (n > left())
    Fail("truncated at byte " + std::to_string(offset_) + " reading " + what + " (" +
         std::to_string(n) + " bytes needed, " + std::to_string(left()) + " left)");
  if (n) std::memcpy(p, bytes_.data() + offset_, n);
  offset_ += n;
}

void BinaryReader::Fail(const std::string& what) const {
  throw CheckpointError("checkpoint '" + name_ + "': " + what);
}

}  // namespace internal
}  // namespace contact
