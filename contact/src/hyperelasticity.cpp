// Finite-strain elasticity of ElasticBody, total Lagrangian (docs/finite-strain.md):
// internal force, stored energy, tangent stiffness, Cauchy stress and the strain measure
// of the small-strain check, for every element type of reference_element.hpp (the
// kernels use only its shape-function gradients and the stiffness rule).
#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "contact/elastic_body.hpp"
#include "reference_element.hpp"
#include "sparsity_pattern.hpp"
#include "text_format.hpp"

namespace contact {
namespace {

using internal::ElementTraits;
using internal::RulePurpose;
using internal::ShapeData;
using Voigt6 = Eigen::Matrix<double, 6, 6>;

// The response of the 3D law at one point: S [Pa], the material tangent D = dS/dE in
// Voigt notation [Pa] (stress [S11, S22, S33, S23, S13, S12] against engineering strain
// [E11, E22, E33, 2E23, 2E13, 2E12]), and W [J/m^3].
struct PointResponse {
  Eigen::Matrix3d S;
  Voigt6 D;
  double W = 0.0;
};

// (I, J) of each Voigt row.
constexpr int kVoigtI[6] = {0, 1, 2, 1, 0, 0};
constexpr int kVoigtJ[6] = {0, 1, 2, 2, 2, 1};

// The 3D law for C = F'F with J = det F > 0.
PointResponse Respond3D(MaterialModel model, double lambda, double mu,
                        const Eigen::Matrix3d& C, double J) {
  PointResponse r;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  if (model == MaterialModel::kNeoHookean) {
    // Bonet and Wood eq. 6.27-6.28: C_IJKL = lambda Ci_IJ Ci_KL
    //   + (mu - lambda ln J)(Ci_IK Ci_JL + Ci_IL Ci_JK).
    const Eigen::Matrix3d Ci = C.inverse();
    const double lnJ = std::log(J);
    r.S = mu * (I - Ci) + lambda * lnJ * Ci;
    r.W = 0.5 * mu * (C.trace() - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
    const double m = mu - lambda * lnJ;
    for (int p = 0; p < 6; ++p)
      for (int q = 0; q < 6; ++q) {
        const int a = kVoigtI[p], b = kVoigtJ[p], c = kVoigtI[q], d = kVoigtJ[q];
        r.D(p, q) = lambda * Ci(a, b) * Ci(c, d) +
                    m * (Ci(a, c) * Ci(b, d) + Ci(a, d) * Ci(b, c));
      }
    return r;
  }
  // Saint Venant-Kirchhoff (and linear elasticity made geometrically exact).
  const Eigen::Matrix3d E = 0.5 * (C - I);
  const double trE = E.trace();
  r.S = lambda * trE * I + 2.0 * mu * E;
  r.W = 0.5 * lambda * trE * trE + mu * E.squaredNorm();
  r.D.setZero();
  r.D.topLeftCorner<3, 3>().setConstant(lambda);
  r.D.diagonal() += Eigen::Matrix<double, 6, 1>(2 * mu, 2 * mu, 2 * mu, mu, mu, mu);
  return r;
}

// The response reduced to the mesh dimension: S (kDim x kDim), D (Voigt of kDim: 2D rows
// [11, 22, 12]), W, and the 3D deformation gradient (for the Cauchy stress).
template <int kDim>
struct ReducedResponse {
  static constexpr int kVoigt = kDim == 2 ? 3 : 6;
  Eigen::Matrix<double, kDim, kDim> S;
  Eigen::Matrix<double, kVoigt, kVoigt> D;
  double W = 0.0;
  Eigen::Matrix3d F3, S3;
};

struct Law {
  MaterialModel model;
  double lambda, mu;  // 3D Lame parameters [Pa]
  PlaneModel plane;
};

ReducedResponse<3> Respond(const Law& law, const Eigen::Matrix3d& F, double J) {
  const PointResponse r = Respond3D(law.model, law.lambda, law.mu, F.transpose() * F, J);
  return {r.S, r.D, r.W, F, r.S};
}

// 2D: plane strain F_zz = 1; plane stress: C_zz = c solves S_zz(c) = 0 by Newton
// (dS_zz/dc = D_zz,zz / 2), and the tangent is condensed,
// D_ab - D_a,zz D_zz,b / D_zz,zz (exact for Saint Venant-Kirchhoff in one step: it gives
// lambda* = 2 lambda mu / (lambda + 2 mu)).
ReducedResponse<2> Respond(const Law& law, const Eigen::Matrix2d& F, double J2) {
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  C.topLeftCorner<2, 2>() = F.transpose() * F;
  double c = 1.0;
  PointResponse r;
  if (law.plane == PlaneModel::kPlaneStress) {
    const double trE = 0.5 * (C(0, 0) + C(1, 1) - 2.0);
    c = std::max(0.1, 1.0 - 2.0 * law.lambda / (law.lambda + 2 * law.mu) * trE);
    for (int iteration = 0; iteration < 50; ++iteration) {
      C(2, 2) = c;
      r = Respond3D(law.model, law.lambda, law.mu, C, J2 * std::sqrt(c));
      const double step = r.S(2, 2) / (0.5 * r.D(2, 2));
      const double next = c - step > 0.0 ? c - step : 0.5 * c;
      const bool converged = std::abs(next - c) <= 1e-15 * c;
      c = next;
      if (converged) break;
    }
  }
  C(2, 2) = c;
  r = Respond3D(law.model, law.lambda, law.mu, C, J2 * std::sqrt(c));
  constexpr int kIn[3] = {0, 1, 5};
  ReducedResponse<2> out;
  out.S = r.S.topLeftCorner<2, 2>();
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q) {
      out.D(p, q) = r.D(kIn[p], kIn[q]);
      if (law.plane == PlaneModel::kPlaneStress)
        out.D(p, q) -= r.D(kIn[p], 2) * r.D(2, kIn[q]) / r.D(2, 2);
    }
  out.W = r.W;
  out.F3.setZero();
  out.F3.topLeftCorner<2, 2>() = F;
  out.F3(2, 2) = std::sqrt(c);
  out.S3 = r.S;
  if (law.plane == PlaneModel::kPlaneStress) out.S3(2, 2) = 0.0;  // (to round-off)
  return out;
}

// What one pass over the elements computes.
struct Outputs {
  Vector* f = nullptr;
  SparseMatrix* K = nullptr;
  Eigen::MatrixXd* sigma = nullptr;
};

template <ElementType T>
struct FiniteStrainElement {
  static constexpr int kDim = ElementTraits<T>::kDim;
  static constexpr int kNodes = ElementTraits<T>::kNodes;
  static constexpr int kDofs = kDim * kNodes;
  static constexpr int kVoigt = kDim == 2 ? 3 : 6;
  using DimMatrix = Eigen::Matrix<double, kDim, kDim>;
  using Gradient = Eigen::Matrix<double, kNodes, kDim>;

  Eigen::Matrix<double, kDofs, 1> f;
  Eigen::Matrix<double, kDofs, kDofs> K;
  Eigen::Matrix3d sigma;
  double energy = 0.0, det_F = 1.0;

  // Element e at displacement u; false (det_F set) if det F <= 0 at a point.
  bool Compute(const Mesh& mesh, int e, const Vector& u, const Law& law, double factor,
               bool tangent) {
    const auto& shape = ShapeData<T>(RulePurpose::kStiffness);
    const auto X = internal::ElementCoordinates<T>(mesh, e);
    Eigen::Matrix<double, kDim, kNodes> U;
    for (int a = 0; a < kNodes; ++a)
      U.col(a) = u.segment<kDim>(kDim * mesh.elements(a, e));
    f.setZero();
    if (tangent) K.setZero();
    sigma.setZero();
    energy = 0.0;
    for (int q = 0; q < shape.NumPoints(); ++q) {
      const DimMatrix Jref = X * shape.dN_dxi[q];
      const Gradient G = shape.dN_dxi[q] * Jref.inverse();  // dN_a / dX_J
      const DimMatrix F = DimMatrix::Identity() + U * G;
      det_F = F.determinant();
      if (!(det_F > 0.0)) return false;
      const double w = factor * shape.weights[q] * Jref.determinant();
      const ReducedResponse<kDim> r = Respond(law, F, det_F);
      // B: d E_voigt / d u_(a,i) = sym(F_iI G_aJ) (engineering shear rows).
      Eigen::Matrix<double, kVoigt, kDofs> B;
      Eigen::Matrix<double, kVoigt, 1> S;
      for (int p = 0; p < kVoigt; ++p) {
        const int I = kDim == 2 ? (p == 2 ? 0 : p) : kVoigtI[p];
        const int J = kDim == 2 ? (p == 2 ? 1 : p) : kVoigtJ[p];
        S(p) = r.S(I, J);
        for (int a = 0; a < kNodes; ++a)
          for (int i = 0; i < kDim; ++i)
            B(p, kDim * a + i) =
                I == J ? F(i, I) * G(a, I) : F(i, I) * G(a, J) + F(i, J) * G(a, I);
      }
      f.noalias() += w * B.transpose() * S;
      energy += w * r.W;
      sigma +=
          (r.F3 * r.S3 * r.F3.transpose()) / (r.F3.determinant() * shape.NumPoints());
      if (!tangent) continue;
      K.noalias() += w * B.transpose() * r.D * B;
      const Eigen::Matrix<double, kNodes, kNodes> geometric = w * G * r.S * G.transpose();
      for (int a = 0; a < kNodes; ++a)
        for (int b = 0; b < kNodes; ++b)
          for (int i = 0; i < kDim; ++i) K(kDim * a + i, kDim * b + i) += geometric(a, b);
    }
    return true;
  }
};

HyperelasticEvaluation Inverted(const Mesh& mesh, int e, double det_F) {
  HyperelasticEvaluation out;
  out.ok = false;
  out.inverted_element = e;
  out.det_F = det_F;
  out.message = mesh.DescribeElement(e) + " at " +
                internal::Format(mesh.ElementCentroid(e)) +
                " m is inverted: det F = " + internal::Format(det_F) +
                " <= 0 at a quadrature point";
  return out;
}

template <ElementType T>
HyperelasticEvaluation EvaluateBody(const ElasticBody& body,
                                    const internal::SparsityPattern* pattern,
                                    const Vector& u, const Law& law, const Outputs& out) {
  using Element = FiniteStrainElement<T>;
  const Mesh& mesh = body.mesh();
  if (u.size() != body.NumDofs())
    throw std::invalid_argument("ElasticBody finite strain: u must have " +
                                std::to_string(body.NumDofs()) +
                                " entries (every dof), got " + std::to_string(u.size()));
  if (out.f) *out.f = Vector::Zero(body.NumDofs());
  if (out.K && pattern) *out.K = pattern->ZeroMatrix();
  if (out.sigma) out.sigma->setZero(9, mesh.NumElements());
  HyperelasticEvaluation result;
  Element element;
  for (int e = 0; e < mesh.NumElements(); ++e) {
    if (!element.Compute(mesh, e, u, law, body.IntegrationFactor(), out.K != nullptr))
      return Inverted(mesh, e, element.det_F);
    result.energy += element.energy;
    if (out.f)
      for (int a = 0; a < Element::kNodes; ++a)
        out.f->segment<Element::kDim>(Element::kDim * mesh.elements(a, e)) +=
            element.f.template segment<Element::kDim>(Element::kDim * a);
    if (out.K) {
      const Eigen::Matrix<double, Element::kDofs, Element::kDofs> Ks =
          0.5 * (element.K + element.K.transpose());
      internal::ScatterElementMatrix(*pattern, mesh.elements.col(e).data(),
                                     Element::kNodes, Ks, out.K);
    }
    if (out.sigma) {
      const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> s = element.sigma;
      out.sigma->col(e) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(s.data());
    }
  }
  return result;
}

// The centre of an element: the mean of its stiffness rule's points (symmetric rules).
template <ElementType T>
const Eigen::Matrix<double, ElementTraits<T>::kNodes, ElementTraits<T>::kDim>&
CentreGradient() {
  static const auto gradient = [] {
    constexpr int kDim = ElementTraits<T>::kDim, kNodes = ElementTraits<T>::kNodes;
    const internal::QuadratureRule& rule =
        internal::ElementRule(T, RulePurpose::kStiffness);
    const Eigen::VectorXd xi = rule.points.rowwise().mean();
    Eigen::Matrix<double, kNodes, 1> N;
    Eigen::Matrix<double, kNodes, kDim, Eigen::RowMajor> dN;
    internal::EvaluateShape(kDim, kNodes, xi.data(), N.data(), dN.data());
    return Eigen::Matrix<double, kNodes, kDim>(dN);
  }();
  return gradient;
}

template <ElementType T>
StrainMeasure MeasureBody(const Mesh& mesh, const Vector& u) {
  constexpr int kDim = ElementTraits<T>::kDim, kNodes = ElementTraits<T>::kNodes;
  using DimMatrix = Eigen::Matrix<double, kDim, kDim>;
  const auto& dN = CentreGradient<T>();
  StrainMeasure m;
  for (int e = 0; e < mesh.NumElements(); ++e) {
    const auto X = internal::ElementCoordinates<T>(mesh, e);
    Eigen::Matrix<double, kDim, kNodes> U;
    for (int a = 0; a < kNodes; ++a)
      U.col(a) = u.segment<kDim>(kDim * mesh.elements(a, e));
    const DimMatrix H = U * dN * (X * dN).inverse();  // Grad u
    const DimMatrix skew = 0.5 * (H - H.transpose());
    const double rotation = skew.norm() / std::sqrt(2.0);  // |axial vector|
    if (rotation > m.rotation) {
      m.rotation = rotation;
      m.rotation_element = e;
    }
    m.spurious_strain =
        std::max(m.spurious_strain, 0.5 * (H.transpose() * H).cwiseAbs().maxCoeff());
    m.resolved_strain =
        std::max(m.resolved_strain, (0.5 * (H + H.transpose())).cwiseAbs().maxCoeff());
  }
  return m;
}

Law LawOf(const ElasticBody& body, MaterialModel model) {
  return {model, body.material().Lambda(), body.material().ShearModulus(),
          body.plane().model};
}

}  // namespace

const char* ToString(MaterialModel m) {
  switch (m) {
    case MaterialModel::kLinear:
      return "linear";
    case MaterialModel::kSaintVenantKirchhoff:
      return "saint-venant-kirchhoff";
    case MaterialModel::kNeoHookean:
      return "neo-hookean";
  }
  return "unknown";
}

MaterialModel MaterialModelFromString(const std::string& name) {
  for (MaterialModel m : {MaterialModel::kLinear, MaterialModel::kSaintVenantKirchhoff,
                          MaterialModel::kNeoHookean})
    if (name == ToString(m)) return m;
  throw std::invalid_argument(
      "material.model must be \"linear\", \"saint-venant-kirchhoff\" "
      "or \"neo-hookean\", got \"" +
      name + "\"");
}

HyperelasticEvaluation ElasticBody::InternalForce(const Vector& u, MaterialModel model,
                                                  Vector* f) const {
  return internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    return EvaluateBody<decltype(tag)::value>(*this, nullptr, u, LawOf(*this, model),
                                              Outputs{f, nullptr, nullptr});
  });
}

HyperelasticEvaluation ElasticBody::StoredEnergy(const Vector& u,
                                                 MaterialModel model) const {
  return internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    return EvaluateBody<decltype(tag)::value>(*this, nullptr, u, LawOf(*this, model),
                                              Outputs{});
  });
}

HyperelasticEvaluation ElasticBody::TangentStiffness(const Vector& u, MaterialModel model,
                                                     SparseMatrix* K) const {
  return internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    return EvaluateBody<decltype(tag)::value>(
        *this, pattern_.get(), u, LawOf(*this, model), Outputs{nullptr, K, nullptr});
  });
}

HyperelasticEvaluation ElasticBody::CauchyStress(const Vector& u, MaterialModel model,
                                                 Eigen::MatrixXd* sigma) const {
  return internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    return EvaluateBody<decltype(tag)::value>(*this, nullptr, u, LawOf(*this, model),
                                              Outputs{nullptr, nullptr, sigma});
  });
}

StrainMeasure ElasticBody::MeasureStrain(const Vector& u) const {
  if (u.size() != NumDofs())
    throw std::invalid_argument("ElasticBody::MeasureStrain: u must have " +
                                std::to_string(NumDofs()) + " entries, got " +
                                std::to_string(u.size()));
  return internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    return MeasureBody<decltype(tag)::value>(mesh_, u);
  });
}

}  // namespace contact
