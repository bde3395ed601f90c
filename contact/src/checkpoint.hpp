// (internal) The checkpoint file of contact::Simulation (contact/simulation.hpp): what it
// holds and its binary format.
//
// File = header, payload, checksum (all integers little-endian as the machine writes
// them; the header's byte-order mark refuses a file of the other order):
//   8 bytes   magic "NCPCKPT\n"
//   u32       format version (kCheckpointVersion)
//   u32       byte-order mark 0x01020304
//   u64       payload length [bytes]
//   payload   the fields of CheckpointData in the order of CheckpointFields
//   u64       FNV-1a 64 of the payload
// Field encodings: integers as i64 or u64, doubles as their 8 bytes (bit for bit),
// strings and vectors as u64 length then the elements, matrices as u64 rows, u64 cols,
// then the column-major entries. The reader checks every length against the bytes left
// before it allocates, so a corrupt or truncated file is refused with CheckpointError,
// never read past its end.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>

#include "contact/contact_system.hpp"
#include "contact/dynamics.hpp"
#include "energy_balance.hpp"

namespace contact::internal {

// 2: StepRecord and DynamicSummary carry krylov_iterations.
// 3: the energy balance and StepRecord carry damping_dissipation (Rayleigh damping).
// 4: DynamicSummary carries the kinematics (finite strain, its switch step, rotation).
inline constexpr std::uint32_t kCheckpointVersion = 4;

/// FNV-1a, 64 bit, of `bytes` (a change detector, not a cryptographic hash).
std::uint64_t Fnv1a(std::string_view bytes, std::uint64_t hash = 0xcbf29ce484222325ULL);

/// What identifies the run a checkpoint belongs to.
struct CheckpointIdentity {
  std::string scene_source;  ///< the scene file's path (for messages; empty for a model)
  std::string scene_text;    ///< its text with the command-line overrides (empty: none)
  std::uint64_t scene_hash = 0;  ///< Fnv1a(scene_text)
  std::string mesh_file;         ///< the gmsh file, empty for a generated mesh
  std::uint64_t mesh_hash = 0;   ///< Fnv1a of its bytes
  std::uint64_t model_hash = 0;  ///< ModelFingerprint
  std::int64_t dim = 0, free_dofs = 0, contact_nodes = 0, num_steps = 0;
  std::int64_t step_method = 0;  ///< StepMethod that runs (auto resolved)
};

/// What the central-difference integrator carries from step k to step k+1 (the
/// integrator's State extends it with f(t_k) and its step buffers; a checkpoint holds it
/// as it is, so saving and restoring are one assignment each).
///   Ku = K u^k,  Mdu_previous = M (u^k - u^{k-1}),  du = u^k - u^{k-1}.
struct CarriedState {
  Eigen::VectorXd u, u_previous;  ///< u^k, u^{k-1} [m]
  Eigen::VectorXd lambda;  ///< lambda^k per contact node [N] (Tresca bounds of step k)
  Eigen::VectorXd Ku, Mdu_previous;  ///< [N], [kg m]
  Eigen::VectorXd du;                ///< the next step's start guess [m]
  double contact_force_max = 0.0;    ///< |r^k|_inf of step k [N]
  ContactSystem::Result contact;     ///< of step k (system units)
};

/// The state after step k (contact/simulation.hpp lists it).
struct CheckpointData {
  CheckpointIdentity identity;
  std::int64_t k = 0;
  CarriedState carried;
  Eigen::VectorXd gaps;  // s_c [m]
  EnergyBalance energy;
  Eigen::MatrixXd warm_start;  // StepAlgorithm::WarmStart
  StepRecord first_inaccurate;
  DynamicSummary summary;  // records of steps 1..k, counts, maxima
  bool has_scene = false;
  Eigen::VectorXd body_force, obstacle_translation;  // [N/m^3], [m] (scene runs)
  std::string application_data;  // e.g. contact-sim's output positions
};

/// A fingerprint of what the trajectory depends on: K, M (pattern and values), the
/// contact nodes (dofs, frames, gaps, areas), dim and the options dt, start and end time,
/// friction, step method and formulation, tolerance, initial state.
std::uint64_t ModelFingerprint(const DynamicModel& model, const DynamicOptions& options);

/// Writes `data` to `path` atomically (ncp::OutputFile: path.partial renamed). Throws
/// ncp::OutputError.
void WriteCheckpoint(const std::string& path, const CheckpointData& data);
/// Reads and checks the format (magic, version, byte order, length, checksum, every
/// field's size). Throws CheckpointError naming the file and what is wrong.
CheckpointData ReadCheckpoint(const std::string& path);
/// The same from bytes in memory (`name` for messages): the fuzz target's entry.
CheckpointData ParseCheckpoint(std::string_view bytes, const std::string& name);

/// Little binary helpers, shared with contact-sim's output positions (application_data).
class BinaryWriter {
 public:
  void Int(std::int64_t v) { Raw(&v, sizeof v); }
  void Unsigned(std::uint64_t v) { Raw(&v, sizeof v); }
  void Double(double v) { Raw(&v, sizeof v); }
  void String(std::string_view s) {
    Unsigned(s.size());
    bytes_.append(s.data(), s.size());
  }
  void Raw(const void* p, std::size_t n) {
    bytes_.append(static_cast<const char*>(p), n);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

/// Reads what BinaryWriter wrote; every read is bounds-checked (CheckpointError "`name`:
/// truncated ... reading `what`").
class BinaryReader {
 public:
  BinaryReader(std::string_view bytes, std::string name)
      : bytes_(bytes), name_(std::move(name)) {}
  std::int64_t Int(const char* what);
  std::uint64_t Unsigned(const char* what);
  double Double(const char* what);
  std::string String(const char* what);
  /// A count of elements of `element_bytes` each that must fit into the bytes left.
  std::uint64_t Count(const char* what, std::size_t element_bytes);
  void Raw(void* p, std::size_t n, const char* what);
  std::size_t left() const { return bytes_.size() - offset_; }
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  std::string_view bytes_;
  std::size_t offset_ = 0;
  std::string name_;
};

}  // namespace contact::internal
