/// \file vtk_writer.hpp
/// Output for ParaView: a mesh with point and cell fields as a VTK XML unstructured grid
/// (.vtu, one per snapshot), the snapshots of a run as a time series (.pvd), and the
/// fields of a contact snapshot (displacement, velocity, gap, contact forces, slip,
/// contact state, stress). The legacy ASCII format (.vtk) is kept for single meshes.
/// Every file is written atomically (NAME.partial, renamed to NAME when complete, see
/// ncp/output_file.hpp); "std::runtime_error if the file cannot be written" below is an
/// ncp::OutputError naming the file and the operating system's reason.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "contact/contact_system.hpp"
#include "contact/elastic_body.hpp"
#include "contact/mesh.hpp"
#include "contact/types.hpp"

namespace contact {

/// A field with one value per mesh node.
struct PointField {
  std::string name;  ///< no spaces (VTK legacy format)
  /// components x NumNodes: 1 row = scalar; dim rows = vector (padded with z = 0 in 2D).
  Eigen::MatrixXd values;
};

/// A field with one value per element (VTK cell data).
struct CellField {
  std::string name;  ///< no spaces
  /// components x NumElements: 1 row = scalar, 3 = vector, 9 = tensor (row-major 3 x 3).
  Eigen::MatrixXd values;
};

/// The point field of a node-major dof vector u (size dim * NumNodes), e.g. the
/// displacement [m]: column i is (u(dim i), ..., u(dim i + dim - 1)).
PointField NodalVectorField(const std::string& name, const Mesh& mesh, const Vector& u);

/// Writes the volume elements of `mesh` with the given point fields. Throws
/// std::invalid_argument if a field has the wrong number of columns, 0 or more than 3
/// rows (other than dim), or a name with spaces, and std::runtime_error if the file
/// cannot be written.
void WriteVtk(const std::string& path, const Mesh& mesh,
              const std::vector<PointField>& point_fields = {});

/// Writes the volume elements of `mesh` with point and cell fields as a VTK XML
/// UnstructuredGrid file (.vtu; data arrays inline in base64 binary, Float64, so every
/// double - NaN too - is stored exactly). Vector point fields with dim rows are padded
/// to 3 components. Throws std::invalid_argument for a field of the wrong size or name
/// (as WriteVtk; cell fields: 1, 3 or 9 rows) and std::runtime_error if the file cannot
/// be written.
void WriteVtu(const std::string& path, const Mesh& mesh,
              const std::vector<PointField>& point_fields,
              const std::vector<CellField>& cell_fields = {});

/// Writes a parallel unstructured grid (.pvtu) that joins pieces written by WriteVtu with
/// the same fields - one per MPI rank, each over its part of the mesh: `fields` gives the
/// point and cell fields of a piece (only their names and number of rows are used), the
/// piece file names are relative to the .pvtu's directory. A .pvd series may list .pvtu
/// files. Throws std::invalid_argument for a bad name or no piece, std::runtime_error if
/// the file cannot be written.
void WritePvtu(const std::string& path, const std::vector<PointField>& point_fields,
               const std::vector<CellField>& cell_fields,
               const std::vector<std::string>& pieces);

/// Writes a ParaView time series (.pvd): one (time [s], file) per snapshot, the file
/// names relative to the .pvd's directory. Throws std::runtime_error if it cannot be
/// written.
void WritePvd(const std::string& path,
              const std::vector<std::pair<double, std::string>>& snapshots);

/// The file name of step `step`'s snapshot, alike in one process and on MPI ranks:
/// "snapshot_" + the step with at least 5 digits + `suffix` (".vtu", ".pvtu",
/// "_rank_3.vtu"), e.g. SnapshotFileName(100, ".pvtu") = "snapshot_00100.pvtu".
std::string SnapshotFileName(int step, const std::string& suffix);

/// State of a contact node in a snapshot (point field contact_state).
enum class ContactState {
  kNotContact = -1,  ///< not a node of Gamma_c
  kOpen = 0,         ///< normal force within the step's force accuracy (round-off) of 0
  kStick = 1,        ///< pressed, slip within the step's displacement accuracy
  kSlip = 2,         ///< pressed and slipping
};

/// Open, stick or slip from the node's normal force lambda [N] and the length of its
/// tangential displacement increment in the step [m], each against the step's accuracy:
/// a force at or below force_accuracy is round-off, not contact (StepRecord::active_nodes
/// counts the same way).
ContactState ClassifyContact(double normal_force, double slip_length,
                             double force_accuracy, double displacement_accuracy);

/// What a snapshot of a dynamic contact run shows. Displacements are of every dof
/// (DofMap::Expand), contact quantities per node of `contact_nodes` in SI units.
struct ContactSnapshot {
  double time = 0.0;             ///< [s]
  Vector displacement;           ///< u^{k+1} [m], every dof
  Vector previous_displacement;  ///< u^k [m], every dof
  double dt = 0.0;               ///< [s]: velocity = (u^{k+1} - u^k) / dt
  const std::vector<ContactNode>* contact_nodes = nullptr;
  Eigen::VectorXd normal_force;        ///< lambda_c >= 0 [N] (on the body, against n_c)
  Eigen::MatrixXd tangent_force;       ///< (dim - 1) x N_c along t1 (, t2) [N]
  Eigen::VectorXd gap;                 ///< gap_c [m] (< 0: penetration)
  double force_accuracy = 0.0;         ///< the step's force accuracy [N]
  double displacement_accuracy = 0.0;  ///< the step's displacement accuracy [m]
  /// Finite strain: the stress field is ElasticBody::CauchyStress with this model (the
  /// Cauchy stress of the deformed body); false: linear, ElementStress.
  bool finite_strain = false;
  MaterialModel finite_strain_model = MaterialModel::kSaintVenantKirchhoff;
};

/// The snapshot of a prescribed initial state u^0, v^0 (every dof of a dim-dimensional
/// mesh) [m], [m/s]: gaps s_c - n_c . u^0_c, contact forces not yet known (NaN, and
/// contact_state NaN).
ContactSnapshot InitialContactSnapshot(int dim, double time, const Vector& u0,
                                       const Vector& v0, double dt,
                                       const std::vector<ContactNode>& contact_nodes);

/// The fields of a snapshot for WriteVtu. Point data: displacement [m], velocity [m/s],
/// gap [m] (NaN off Gamma_c), normal_force [N] (lambda_c n_c: the force of the obstacle
/// on the body, pointing into the body), friction_force [N] (the vector sum_a tau_a t_a),
/// slip [m] (the tangential part of u^{k+1} - u^k at a contact node), contact_state
/// (ContactState: -1 off Gamma_c, 0 open, 1 stick, 2 slip; NaN where the normal force is
/// NaN, i.e. not known), contact_normal (n_c, the unit normal of the node's contact
/// frame, from the body towards the obstacle: the obstacle's surface near the node is at
/// x + u + gap n_c); contact quantities are 0 at nodes off Gamma_c. Cell data: stress
/// [Pa], the Cauchy stress sigma = D eps(u) averaged over the element's stiffness
/// quadrature points (a 3 x 3 tensor; in 2D sigma_zz = lambda (eps_xx + eps_yy) in plane
/// strain, 0 in plane stress), and von_mises [Pa]. Throws std::invalid_argument for
/// arrays of the wrong size.
std::pair<std::vector<PointField>, std::vector<CellField>> ContactSnapshotFields(
    const ElasticBody& body, const ContactSnapshot& snapshot);

/// The stress of displacement u (every dof) [m] in every element: 9 x NumElements, the
/// row-major 3 x 3 Cauchy stress [Pa] averaged over the stiffness quadrature points.
Eigen::MatrixXd ElementStress(const ElasticBody& body, const Vector& u);

/// Writes the snapshots of a run into a directory: snapshot_NNNNN.vtu (NNNNN = the step)
/// and solution.pvd listing every snapshot written so far, which ParaView opens as one
/// time series.
class VtuSeriesWriter {
 public:
  VtuSeriesWriter(std::string directory, const ElasticBody& body);
  /// Writes the snapshot of `step` and rewrites solution.pvd; returns the .vtu's path.
  std::string Write(int step, const ContactSnapshot& snapshot);
  std::string pvd_path() const;
  /// (time [s], file name) of every snapshot written, in order.
  const std::vector<std::pair<double, std::string>>& snapshots() const {
    return snapshots_;
  }
  /// Continues a series (a resumed run): `snapshots` as snapshots() returned them, the
  /// .pvd rewritten to list exactly these. Throws ncp::OutputError.
  void Continue(std::vector<std::pair<double, std::string>> snapshots);

 private:
  std::string directory_;
  const ElasticBody& body_;
  std::vector<std::pair<double, std::string>> snapshots_;
};

}  // namespace contact
