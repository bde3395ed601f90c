#include "contact/elastic_body.hpp"

#include <Eigen/StdVector>
#include <algorithm>
#include <stdexcept>
#include <string>

#include "boundary_geometry.hpp"
#include "parallel.hpp"
#include "reference_element.hpp"
#include "sparsity_pattern.hpp"

namespace contact {
namespace {

using internal::ElementTraits;
using internal::RulePurpose;
using internal::ShapeData;

// Isoparametric map at one integration point: det(dx/dxi) and the physical gradients
// dN_a/dx_k = sum_l dN_a/dxi_l (J^-1)_lk, with J_kl = dx_k/dxi_l.
template <ElementType T>
struct PhysicalGradient {
  static constexpr int kDim = ElementTraits<T>::kDim;
  static constexpr int kNodes = ElementTraits<T>::kNodes;
  double det = 0;
  Eigen::Matrix<double, kNodes, kDim> G;

  PhysicalGradient(const Eigen::Matrix<double, kDim, kNodes>& X,
                   const Eigen::Matrix<double, kNodes, kDim>& dN_dxi) {
    const Eigen::Matrix<double, kDim, kDim> J = X * dN_dxi;
    det = J.determinant();
    G = dN_dxi * J.inverse();
  }
};

// Element stiffness from the weighted gradient products
//   A_(a,k),(b,l) = sum_q w_q dN_a/dx_k dN_b/dx_l   (w_q = factor * weight * det J),
// as K_(a,i),(b,j) = lambda A_(a,i),(b,j) + mu A_(a,j),(b,i) + mu delta_ij sum_k
// A_(a,k),(b,k) (the bilinear form lambda div u div v + 2 mu eps(u) : eps(v)). A = V^T
// diag(w) V with V_q,(a,k) = dN_a/dx_k at point q is one small matrix product per
// element; A is made exactly symmetric so that K is.
template <ElementType T>
struct ElementStiffness {
  static constexpr int kDim = ElementTraits<T>::kDim;
  static constexpr int kNodes = ElementTraits<T>::kNodes;
  static constexpr int kDofs = kDim * kNodes;
  using Matrix = Eigen::Matrix<double, kDofs, kDofs>;

  static void Compute(const Mesh& mesh, int e, double lambda, double mu, double factor,
                      Matrix* Ke) {
    constexpr int kPoints = ElementTraits<T>::kStiffnessPoints;
    const auto& shape = ShapeData<T>(RulePurpose::kStiffness);
    Eigen::Matrix<double, kPoints, kDofs, Eigen::RowMajor> V, WV;
    Matrix A;
    const auto X = internal::ElementCoordinates<T>(mesh, e);
    for (int q = 0; q < kPoints; ++q) {
      const PhysicalGradient<T> map(X, shape.dN_dxi[q]);
      const double w = factor * shape.weights[q] * map.det;
      for (int a = 0; a < kNodes; ++a)
        for (int k = 0; k < kDim; ++k) {
          V(q, kDim * a + k) = map.G(a, k);
          WV(q, kDim * a + k) = w * map.G(a, k);
        }
    }
    A.noalias() = V.transpose() * WV;
    A = (A + A.transpose()).eval() * 0.5;
    for (int b = 0; b < kNodes; ++b)
      for (int a = 0; a < kNodes; ++a) {
        double trace = 0;
        for (int k = 0; k < kDim; ++k) trace += A(kDim * a + k, kDim * b + k);
        for (int j = 0; j < kDim; ++j)
          for (int i = 0; i < kDim; ++i)
            (*Ke)(kDim * a + i, kDim * b + j) = lambda * A(kDim * a + i, kDim * b + j) +
                                                mu * A(kDim * a + j, kDim * b + i) +
                                                (i == j ? mu * trace : 0.0);
      }
  }
};

// Scalar element mass rho h int N_a N_b (the same on every component).
template <ElementType T>
struct ElementMass {
  static constexpr int kNodes = ElementTraits<T>::kNodes;
  using Matrix = Eigen::Matrix<double, kNodes, kNodes>;

  static void Compute(const Mesh& mesh, int e, double rho, double factor, Matrix* Me) {
    const auto& shape = ShapeData<T>(RulePurpose::kMass);
    const auto X = internal::ElementCoordinates<T>(mesh, e);
    Me->setZero();
    for (int q = 0; q < shape.NumPoints(); ++q) {
      const double det = (X * shape.dN_dxi[q]).determinant();
      Me->noalias() +=
          (factor * rho * shape.weights[q] * det) * shape.N[q] * shape.N[q].transpose();
    }
  }
};

// Assembly in batches: the element matrices of a batch are computed in parallel (each
// thread its own elements), then added in element order by one thread, so the assembled
// matrix is bit-for-bit that of a serial loop for any number of threads.
template <class ElementMatrix, class Compute, class Scatter>
void AssembleInBatches(int num_elements, const Compute& compute, const Scatter& scatter) {
  // At most 2048 element matrices and about 16 MB per batch (a Hexahedron27 matrix is
  // 81 x 81).
  constexpr int kBatch = static_cast<int>(std::max<std::size_t>(
      64, std::min<std::size_t>(2048, (16u << 20) / sizeof(ElementMatrix))));
  std::vector<ElementMatrix, Eigen::aligned_allocator<ElementMatrix>> batch(
      static_cast<size_t>(std::min(kBatch, num_elements)));
  for (int first = 0; first < num_elements; first += kBatch) {
    const int count = std::min(kBatch, num_elements - first);
    internal::ParallelFor(0, count, 256, [&](long b) {
      compute(first + static_cast<int>(b), &batch[static_cast<size_t>(b)]);
    });
    for (int b = 0; b < count; ++b) scatter(first + b, batch[static_cast<size_t>(b)]);
  }
}

template <ElementType T>
void AssembleStiffness(const Mesh& mesh, const internal::SparsityPattern& pattern,
                       double lambda, double mu, double factor, SparseMatrix* K) {
  using Element = ElementStiffness<T>;
  if (ShapeData<T>(RulePurpose::kStiffness).NumPoints() !=
      ElementTraits<T>::kStiffnessPoints)
    throw std::logic_error("stiffness rule size mismatch");
  AssembleInBatches<typename Element::Matrix>(
      mesh.NumElements(),
      [&](int e, typename Element::Matrix* Ke) {
        Element::Compute(mesh, e, lambda, mu, factor, Ke);
      },
      [&](int e, const typename Element::Matrix& Ke) {
        internal::ScatterElementMatrix(pattern, mesh.elements.col(e).data(),
                                       Element::kNodes, Ke, K);
      });
}

template <ElementType T>
void AssembleMass(const Mesh& mesh, const internal::SparsityPattern& pattern, double rho,
                  double factor, SparseMatrix* M) {
  using Element = ElementMass<T>;
  ShapeData<T>(RulePurpose::kMass);  // (built here, before the threads start)
  AssembleInBatches<typename Element::Matrix>(
      mesh.NumElements(),
      [&](int e, typename Element::Matrix* Me) {
        Element::Compute(mesh, e, rho, factor, Me);
      },
      [&](int e, const typename Element::Matrix& Me) {
        internal::ScatterBlockDiagonalElementMatrix(pattern, mesh.elements.col(e).data(),
                                                    Element::kNodes, Me, M);
      });
}

// f_(a,i) += factor int N_a value_i(x) dV over all elements, with value = weight(x) *
// v(x) and v evaluated by `field` at each integration point.
template <ElementType T, class Field>
void IntegrateAgainstShapeFunctions(const Mesh& mesh, double factor, const Field& field,
                                    Vector* f) {
  constexpr int kDim = ElementTraits<T>::kDim;
  constexpr int kNodes = ElementTraits<T>::kNodes;
  const auto& shape = ShapeData<T>(RulePurpose::kMass);
  for (int e = 0; e < mesh.NumElements(); ++e) {
    const auto X = internal::ElementCoordinates<T>(mesh, e);
    for (int q = 0; q < shape.NumPoints(); ++q) {
      const double w = factor * shape.weights[q] * (X * shape.dN_dxi[q]).determinant();
      const Eigen::VectorXd value = field(Eigen::VectorXd(X * shape.N[q]));
      for (int a = 0; a < kNodes; ++a)
        for (int i = 0; i < static_cast<int>(value.size()); ++i)
          (*f)(kDim * mesh.elements(a, e) + i) += w * shape.N[q](a) * value(i);
    }
  }
}

// HRZ lumping (Hinton, Rock & Zienkiewicz 1976): the diagonal of the consistent element
// mass scaled to the element's total mass, m_a = M_aa * (sum_ab M_ab) / (sum_b M_bb). It
// is positive for every element (M_aa = rho h int N_a^2 dV > 0), unlike the row sums
// h int rho N_a dV, which are zero at Triangle6 corners and negative at Tetrahedron10 and
// serendipity corners.
template <ElementType T>
void AddHrzLumpedMass(const Mesh& mesh, double rho, double factor, Vector* m) {
  constexpr int kDim = ElementTraits<T>::kDim;
  typename ElementMass<T>::Matrix Me;
  for (int e = 0; e < mesh.NumElements(); ++e) {
    ElementMass<T>::Compute(mesh, e, rho, factor, &Me);
    const double scale = Me.sum() / Me.trace();
    for (int a = 0; a < ElementMass<T>::kNodes; ++a)
      for (int i = 0; i < kDim; ++i)
        (*m)(kDim * mesh.elements(a, e) + i) += scale * Me(a, a);
  }
}

void CheckVectorSize(const Eigen::VectorXd& value, int dim, const char* what) {
  if (value.size() != dim)
    throw std::invalid_argument(std::string(what) + " must have " + std::to_string(dim) +
                                " components (the mesh dimension), got " +
                                std::to_string(value.size()));
}

}  // namespace

ElasticBody::ElasticBody(Mesh mesh, const IsotropicMaterial& material,
                         const PlaneSettings& plane)
    : mesh_(std::move(mesh)), material_(material), plane_(plane) {
  material_.Validate();
  ValidateMesh(mesh_);
  if (mesh_.dim == 2) plane_.Validate();
  pattern_ = std::make_shared<const internal::SparsityPattern>(mesh_);
}

double ElasticBody::IntegrationFactor() const {
  return mesh_.dim == 2 ? plane_.thickness : 1.0;
}

long long ElasticBody::NumNonZeros() const { return pattern_->NumNonZeros(); }

SparseMatrix ElasticBody::StiffnessMatrix() const {
  const double mu = material_.ShearModulus();
  const double lambda = ElasticityMatrix(material_, mesh_.dim, plane_.model)(0, 1);
  SparseMatrix K = pattern_->ZeroMatrix();
  internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    AssembleStiffness<decltype(tag)::value>(mesh_, *pattern_, lambda, mu,
                                            IntegrationFactor(), &K);
  });
  return K;
}

SparseMatrix ElasticBody::ConsistentMassMatrix() const {
  SparseMatrix M = pattern_->ZeroMatrix();
  internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    AssembleMass<decltype(tag)::value>(mesh_, *pattern_, material_.density,
                                       IntegrationFactor(), &M);
  });
  return M;
}

Vector ElasticBody::LumpedMass() const {
  Vector m = Vector::Zero(NumDofs());
  if (ElementOrder(mesh_.element_type) == 2) {
    internal::DispatchElement(mesh_.element_type, [&](auto tag) {
      AddHrzLumpedMass<decltype(tag)::value>(mesh_, material_.density,
                                             IntegrationFactor(), &m);
    });
    return m;
  }
  // Linear elements: row sums of M (sum_b N_b = 1, so m_(a,i) = h int rho N_a dV).
  const Eigen::VectorXd ones = Eigen::VectorXd::Constant(mesh_.dim, material_.density);
  internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    IntegrateAgainstShapeFunctions<decltype(tag)::value>(
        mesh_, IntegrationFactor(), [&](const Eigen::VectorXd&) { return ones; }, &m);
  });
  return m;
}

Vector ElasticBody::BodyForceLoad(const Eigen::VectorXd& b) const {
  CheckVectorSize(b, mesh_.dim, "BodyForceLoad: body force density b");
  return BodyForceFieldLoad([b](const Eigen::VectorXd&) { return b; });
}

Vector ElasticBody::BodyForceFieldLoad(const BodyForceField& b) const {
  if (!b) throw std::invalid_argument("BodyForceFieldLoad: empty body force function");
  Vector f = Vector::Zero(NumDofs());
  internal::DispatchElement(mesh_.element_type, [&](auto tag) {
    IntegrateAgainstShapeFunctions<decltype(tag)::value>(
        mesh_, IntegrationFactor(),
        [&](const Eigen::VectorXd& x) {
          Eigen::VectorXd value = b(x);
          CheckVectorSize(value, mesh_.dim,
                          "BodyForceFieldLoad: body force density b(x)");
          return value;
        },
        &f);
  });
  return f;
}

Vector ElasticBody::TractionLoad(const Eigen::VectorXd& t,
                                 const std::string& group) const {
  CheckVectorSize(t, mesh_.dim, "TractionLoad: traction t");
  return TractionFieldLoad(
      [t](const Eigen::VectorXd&, const Eigen::VectorXd&) { return t; }, group);
}

Vector ElasticBody::TractionFieldLoad(const TractionField& t,
                                      const std::string& group) const {
  if (!t) throw std::invalid_argument("TractionFieldLoad: empty traction function");
  const BoundaryFacets& facets = mesh_.BoundaryGroup(group);
  const auto points = internal::FacetIntegrationPoints(mesh_, group);
  Vector f = Vector::Zero(NumDofs());
  const int dim = mesh_.dim;
  for (int facet = 0; facet < facets.NumFacets(); ++facet) {
    for (const internal::FacetPoint& point : points[facet]) {
      const Eigen::VectorXd value = t(point.x, point.normal);
      CheckVectorSize(value, dim, "TractionFieldLoad: traction t(x, n)");
      const double w = IntegrationFactor() * point.weight_dS;
      for (int a = 0; a < point.N.size(); ++a)
        for (int i = 0; i < dim; ++i)
          f(dim * facets.connectivity(a, facet) + i) += w * point.N(a) * value(i);
    }
  }
  return f;
}

}  // namespace contact
