/// \file elastic_body.hpp
/// The discretized elastic body: stiffness K, consistent mass M, lumped mass and load
/// vectors of the semi-discrete equation of motion (thesis section 4.2, eq. 56)
///     M u'' + K u = f,
/// for isotropic linear elasticity under the small-displacement assumption.
///
/// Dof layout: node-major, dof = dim * node + component (component 0 = x, 1 = y, 2 = z).
/// In 2D every integral carries the factor PlaneSettings::thickness h.
///
/// Assembly: K and M share one compressed-column pattern built from the node graph once
/// (in the constructor); element matrices are added in place, so assembly is linear in
/// the number of elements and never holds a dense N x N matrix or a triplet list.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "contact/hyperelastic_material.hpp"
#include "contact/material.hpp"
#include "contact/mesh.hpp"
#include "contact/types.hpp"

namespace contact {

namespace internal {
struct SparsityPattern;
}

/// A body force density b(x) [N/m^3], returning a vector of size dim.
using BodyForceField = std::function<Eigen::VectorXd(const Eigen::VectorXd& x)>;
/// A surface traction t(x, n) [N/m^2] (force per deformed = undeformed area), given the
/// point x and the outward unit normal n of the boundary there; returns size dim.
/// A pressure p is t = -p n.
using TractionField =
    std::function<Eigen::VectorXd(const Eigen::VectorXd& x, const Eigen::VectorXd& n)>;

class ElasticBody {
 public:
  /// Validates the mesh (ValidateMesh: throws on inverted elements), the material and, in
  /// 2D, the plane settings; builds the sparsity pattern.
  ElasticBody(Mesh mesh, const IsotropicMaterial& material,
              const PlaneSettings& plane = {});

  const Mesh& mesh() const { return mesh_; }
  const IsotropicMaterial& material() const { return material_; }
  const PlaneSettings& plane() const { return plane_; }
  int dim() const { return mesh_.dim; }
  int NumDofs() const { return mesh_.NumDofs(); }
  /// The factor of every integral: the thickness h in 2D, 1 in 3D [m or 1].
  double IntegrationFactor() const;

  /// Stiffness [N/m], the bilinear form h int sigma(u) : eps(v) dV:
  ///   K_(a,i),(b,j) = h int ( lambda dN_a/dx_i dN_b/dx_j + mu dN_a/dx_j dN_b/dx_i
  ///                           + mu delta_ij grad N_a . grad N_b ) dV,
  /// with lambda* = E nu / (1 - nu^2) in plane stress. Symmetric positive semidefinite;
  /// its null space is the rigid-body motions.
  SparseMatrix StiffnessMatrix() const;
  /// Consistent mass M_{(a,i),(b,j)} = delta_ij h int rho N_a N_b dV [kg].
  SparseMatrix ConsistentMassMatrix() const;
  /// Lumped mass, one entry per dof (the diagonal of the lumped mass matrix) [kg]. Linear
  /// elements: row sums m_(a,i) = sum_b M_{(a,i),(b,i)} = h int rho N_a dV. Quadratic
  /// elements: HRZ diagonal scaling (Hinton, Rock & Zienkiewicz 1976) per element,
  /// m_a = M_aa (sum_bc M_bc) / (sum_b M_bb), positive and summing to the element's mass.
  Vector LumpedMass() const;
  /// Structural nonzeros of K and M.
  long long NumNonZeros() const;

  /// f_(a,i) = h int N_a b_i dV [N] for a constant body force density b [N/m^3] (size
  /// dim), e.g. gravity b = rho g.
  Vector BodyForceLoad(const Eigen::VectorXd& b) const;
  /// The same for a body force density field b(x) [N/m^3], integrated with the mass rule.
  Vector BodyForceFieldLoad(const BodyForceField& b) const;
  /// f_(a,i) = h int_group N_a t_i dS [N] for a constant traction t [N/m^2] (size dim) on
  /// a boundary group (by default "load"). Throws if the group is missing.
  Vector TractionLoad(const Eigen::VectorXd& t,
                      const std::string& group = kLoadGroup) const;
  /// The same for a traction field t(x, n) [N/m^2], integrated with the facet rule (exact
  /// for t linear in x on straight facets).
  Vector TractionFieldLoad(const TractionField& t,
                           const std::string& group = kLoadGroup) const;

  /// Finite strain, total Lagrangian (contact/hyperelastic_material.hpp,
  /// docs/finite-strain.md), for the full displacement u (NumDofs) [m]; integrals with
  /// the stiffness rule. In 2D plane strain F_zz = 1; plane stress solves S_zz = 0 for
  /// C_zz at every quadrature point (Newton) and condenses the tangent.
  /// Internal force f_(a,i) = h int P_iJ dN_a/dX_J dV_0 [N] into *f (resized), and the
  /// stored energy h int W dV_0 [J]. Zero for any rigid motion u = (R - I) X + c.
  HyperelasticEvaluation InternalForce(const Vector& u, MaterialModel model,
                                       Vector* f) const;
  /// The stored energy alone [J].
  HyperelasticEvaluation StoredEnergy(const Vector& u, MaterialModel model) const;
  /// The tangent stiffness d f_int / d u [N/m] (material plus geometric part, symmetric)
  /// into *K (the pattern of StiffnessMatrix); at u = 0 it equals StiffnessMatrix().
  HyperelasticEvaluation TangentStiffness(const Vector& u, MaterialModel model,
                                          SparseMatrix* K) const;
  /// Cauchy stress sigma = F S F' / J [Pa] per element (the mean over the stiffness
  /// rule's points), in the deformed configuration: 9 x NumElements, the row-major
  /// 3 x 3 tensor as ElementStress (vtk_writer.hpp) (2D: sigma_zz = S_zz / J in plane
  /// strain, 0 in plane stress).
  HyperelasticEvaluation CauchyStress(const Vector& u, MaterialModel model,
                                      Eigen::MatrixXd* sigma) const;
  /// Rotation and spurious strain of the linear model at u (StrainMeasure).
  StrainMeasure MeasureStrain(const Vector& u) const;

 private:
  Mesh mesh_;
  IsotropicMaterial material_;
  PlaneSettings plane_;
  /// Shared by K and M and by copies of the body; immutable.
  std::shared_ptr<const internal::SparsityPattern> pattern_;
};

}  // namespace contact
