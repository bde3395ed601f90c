#include "contact/contact_system.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace contact {
namespace {

using Triplet = Eigen::Triplet<double, int>;

std::string NodeName(size_t c, const ContactNode& node) {
  return "contact node #" + std::to_string(c) + " (mesh node " +
         std::to_string(node.node) + ")";
}

// M (rows x cols) gets the pattern of `entries` (repeated (row, col) merged, explicit
// zeros kept, compressed, sorted) and (*position)[k] = the index of entries[k] in M's
// value array.
template <typename Matrix>
void BuildPattern(Eigen::Index rows, Eigen::Index cols,
                  const std::vector<Triplet>& entries, Matrix* M,
                  std::vector<int>* position) {
  M->resize(rows, cols);
  M->setFromTriplets(entries.begin(), entries.end());
  M->makeCompressed();
  position->resize(entries.size());
  for (size_t k = 0; k < entries.size(); ++k) {
    const int outer = Matrix::IsRowMajor ? entries[k].row() : entries[k].col();
    const int inner = Matrix::IsRowMajor ? entries[k].col() : entries[k].row();
    const int* begin = M->innerIndexPtr() + M->outerIndexPtr()[outer];
    const int* end = M->innerIndexPtr() + M->outerIndexPtr()[outer + 1];
    (*position)[k] =
        static_cast<int>(std::lower_bound(begin, end, inner) - M->innerIndexPtr());
  }
}

bool SamePattern(const ncp::SparseMatrix& a, const ncp::SparseMatrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a.isCompressed() &&
         b.isCompressed() && a.nonZeros() == b.nonZeros() &&
         std::equal(b.outerIndexPtr(), b.outerIndexPtr() + b.outerSize() + 1,
                    a.outerIndexPtr()) &&
         std::equal(b.innerIndexPtr(), b.innerIndexPtr() + b.nonZeros(),
                    a.innerIndexPtr());
}

}  // namespace

ncp::Options ContactNcpOptions() {
  ncp::Options options;
  options.min_tie_takes_b = true;
  // Monotone Armijo search: on the 3D friction steps (eq. 94) of the closed-form checks
  // (contact-physics-check --quick --dim 3, lumped mass) the nonmonotone default of ncp
  // ended two sliding runs with a failed step where the monotone search failed none.
  options.nonmonotone_memory = 1;
  return options;
}

void CompleteContactFrame(int dim, ContactNode* node) {
  const Eigen::Vector3d& n = node->normal;
  std::vector<int> constrained;
  for (int a = 0; a < dim; ++a)
    if (node->dofs[a] < 0) constrained.push_back(a);
  if (dim == 2) {
    node->tangent1 = Eigen::Vector3d(-n.y(), n.x(), 0.0);
    node->tangent2.setZero();
    return;
  }
  if (constrained.size() == 1) {
    // The free tangent lies in the plane of the free axes; the constrained axis follows.
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(constrained[0]);
    node->tangent1 = e.cross(n).normalized();
    node->tangent2 = n.cross(node->tangent1);
    return;
  }
  // t1 orthogonal to n, built from the coordinate axis least aligned with n (with two
  // constrained axes this is one of them, and both tangents are constrained directions).
  Eigen::Index axis;
  n.cwiseAbs().minCoeff(&axis);
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
  node->tangent1 = (e - e.dot(n) * n).normalized();
  node->tangent2 = n.cross(node->tangent1);
}

RestrictionMaps MakeRestrictionMaps(int dim, int num_free_dofs,
                                    const std::vector<ContactNode>& nodes) {
  const std::string who = "contact::MakeRestrictionMaps: ";
  const int n = num_free_dofs;
  if (dim != 2 && dim != 3)
    throw std::invalid_argument(who + "dimension must be 2 or 3, got " +
                                std::to_string(dim));
  if (n < 0)
    throw std::invalid_argument(who + "num_free_dofs must be >= 0, got " +
                                std::to_string(n));
  // Validate the nodes and build R: R[slot a, dof of free axis b] = frame_a(axis b),
  // where the slots of a node are the dofs of its free components, normal first.
  std::vector<int> owner(static_cast<size_t>(n), -1);  // contact node of each dof
  std::vector<int> local(static_cast<size_t>(n), -1);  // local component of each slot
  std::vector<Triplet> rotation;
  rotation.reserve(static_cast<size_t>(n) + 9 * nodes.size());
  for (size_t c = 0; c < nodes.size(); ++c) {
    const ContactNode& node = nodes[c];
    int free_axes[3], slots[3], num_free = 0;
    for (int a = 0; a < dim; ++a) {
      const int dof = node.dofs[a];
      if (dof < -1 || dof >= n)
        throw std::invalid_argument(who + NodeName(c, node) + ": dof " +
                                    std::to_string(dof) + " of component " +
                                    std::to_string(a) + " is neither a free dof in [0, " +
                                    std::to_string(n) + ") nor -1 (constrained)");
      if (dof < 0) continue;
      if (owner[static_cast<size_t>(dof)] >= 0)
        throw std::invalid_argument(who + NodeName(c, node) + ": dof " +
                                    std::to_string(dof) +
                                    " is shared with another contact node or component");
      owner[static_cast<size_t>(dof)] = static_cast<int>(c);
      free_axes[num_free] = a;
      slots[num_free++] = dof;
    }
    if (num_free == 0)
      throw std::invalid_argument(who + NodeName(c, node) +
                                  ": all components are constrained");
    const Eigen::Vector3d frame[3] = {node.normal, node.tangent1, node.tangent2};
    for (int a = 0; a < num_free; ++a) {
      if (std::abs(frame[a].norm() - 1.0) > 1e-12)
        throw std::invalid_argument(who + NodeName(c, node) + ": frame vector " +
                                    std::to_string(a) + " is not a unit vector");
      for (int b = 0; b < a; ++b)
        if (std::abs(frame[a].dot(frame[b])) > 1e-12)
          throw std::invalid_argument(who + NodeName(c, node) +
                                      ": frame is not orthogonal");
      for (int axis = 0; axis < 3; ++axis) {
        const bool is_free =
            std::find(free_axes, free_axes + num_free, axis) != free_axes + num_free;
        if (!is_free && std::abs(frame[a](axis)) > 1e-12)
          throw std::invalid_argument(
              who + NodeName(c, node) + ": frame vector " + std::to_string(a) +
              " has a component along axis " + std::to_string(axis) +
              (axis < dim
                   ? ", which is constrained (the normal must lie in the free directions)"
                   : " in 2D"));
      }
      local[static_cast<size_t>(slots[a])] = a;
      for (int b = 0; b < num_free; ++b)
        rotation.emplace_back(slots[a], slots[b], frame[a](free_axes[b]));
    }
    if (!std::isfinite(node.gap))
      throw std::invalid_argument(who + NodeName(c, node) + ": gap is not finite");
  }
  RestrictionMaps maps;
  std::vector<Triplet> x, y, z;
  for (int i = 0; i < n; ++i) {
    const int a = local[static_cast<size_t>(i)];
    if (owner[static_cast<size_t>(i)] < 0) {
      rotation.emplace_back(i, i, 1.0);
      x.emplace_back(static_cast<int>(x.size()), i, 1.0);
    } else if (a == 0) {
      y.emplace_back(owner[static_cast<size_t>(i)], i, 1.0);
    } else {
      z.emplace_back(static_cast<int>(z.size()), i, 1.0);
    }
  }
  maps.R.resize(n, n);
  maps.R.setFromTriplets(rotation.begin(), rotation.end());
  maps.X.resize(static_cast<Eigen::Index>(x.size()), n);
  maps.X.setFromTriplets(x.begin(), x.end());
  maps.Y.resize(static_cast<Eigen::Index>(nodes.size()), n);
  maps.Y.setFromTriplets(y.begin(), y.end());
  maps.Z.resize(static_cast<Eigen::Index>(z.size()), n);
  maps.Z.setFromTriplets(z.begin(), z.end());
  return maps;
}

ContactSystem::ContactSystem(int dim, const Eigen::SparseMatrix<double>& S,
                             std::vector<ContactNode> nodes)
    : dim_(dim), n_(static_cast<int>(S.rows())), nodes_(std::move(nodes)) {
  if (S.rows() != S.cols())
    throw std::invalid_argument("contact::ContactSystem: S must be square, got " +
                                std::to_string(S.rows()) + " x " +
                                std::to_string(S.cols()));
  rotation_ = MakeRestrictionMaps(dim, n_, nodes_).R;  // validates the nodes
  layout_.resize(nodes_.size());
  for (size_t c = 0; c < nodes_.size(); ++c) {
    Layout& L = layout_[c];
    for (int a = 0; a < dim; ++a)
      if (nodes_[c].dofs[a] >= 0) L.slot[L.num_free++] = nodes_[c].dofs[a];
    L.tangent_dim = L.num_free - 1;
  }
  S_local_ = rotation_ * S * rotation_.transpose();
  for (Eigen::Index i = 0; i < S_local_.outerSize(); ++i) {
    double sum = 0.0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(S_local_, i); it;
         ++it)
      sum += std::abs(it.value());
    s_row_sum_ = std::max(s_row_sum_, sum);
  }
  y_.resize(n_);
  r_.resize(n_);
  Update(Eigen::VectorXd::Zero(n_), Eigen::VectorXd::Zero(n_), Eigen::VectorXd());
}

void ContactSystem::SetGaps(const Eigen::VectorXd& gaps) {
  const std::string who = "contact::ContactSystem::SetGaps: ";
  if (gaps.size() != static_cast<Eigen::Index>(nodes_.size()))
    throw std::invalid_argument(who + "one gap per contact node (" +
                                std::to_string(nodes_.size()) + ") is needed, got " +
                                std::to_string(gaps.size()));
  for (size_t c = 0; c < nodes_.size(); ++c) {
    const double s = gaps(static_cast<Eigen::Index>(c));
    if (!std::isfinite(s))
      throw std::invalid_argument(who + NodeName(c, nodes_[c]) + ": gap is not finite");
    nodes_[c].gap = s;
  }
}

void ContactSystem::Update(const Eigen::VectorXd& q, const Eigen::VectorXd& u0,
                           const Eigen::VectorXd& tresca_bound) {
  const char* who = "contact::ContactSystem::Update: ";
  if (q.size() != n_ || u0.size() != n_)
    throw std::invalid_argument(std::string(who) + "q and u0 must have size " +
                                std::to_string(n_) + ", got " + std::to_string(q.size()) +
                                " and " + std::to_string(u0.size()));
  const auto num_nodes = static_cast<Eigen::Index>(nodes_.size());
  if (tresca_bound.size() != 0 && tresca_bound.size() != num_nodes)
    throw std::invalid_argument(
        std::string(who) +
        "tresca_bound must be empty or have one entry per contact node (" +
        std::to_string(num_nodes) + "), got " + std::to_string(tresca_bound.size()));
  q_local_.noalias() = rotation_ * q;
  u0_local_.noalias() = rotation_ * u0;
  gap0_.resize(num_nodes);
  for (Eigen::Index c = 0; c < num_nodes; ++c)
    gap0_(c) = nodes_[static_cast<size_t>(c)].gap -
               u0_local_(layout_[static_cast<size_t>(c)].slot[0]);
  if (tresca_bound.size())
    bound_ = tresca_bound;
  else
    bound_.setZero(num_nodes);

  // Friction unknowns at nodes with g_c > 0 and at least one free tangent.
  row_kind_.assign(static_cast<size_t>(n_), 0);
  num_friction_ = 0;
  int extra = n_, num_unit_rows = 0;
  for (size_t c = 0; c < nodes_.size(); ++c) {
    Layout& L = layout_[c];
    const double g = bound_(static_cast<Eigen::Index>(c));
    if (!(g >= 0.0) || !std::isfinite(g))
      throw std::invalid_argument(who + NodeName(c, nodes_[c]) +
                                  ": Tresca bound must be finite and >= 0, got " +
                                  std::to_string(g));
    row_kind_[static_cast<size_t>(L.slot[0])] = 1;
    const bool had_friction = L.friction >= 0;
    L.friction = L.extra = L.unit_row = -1;
    if (g > 0.0 && L.tangent_dim > 0) {
      L.friction = num_friction_++;
      L.extra = extra;
      extra += L.tangent_dim == 1 ? 2 : 3;
      if (L.tangent_dim == 2) L.unit_row = num_unit_rows++;
      for (int a = 1; a < L.num_free; ++a) row_kind_[static_cast<size_t>(L.slot[a])] = 2;
    }
    // The Jacobian patterns follow the set of friction nodes (all else is fixed by it).
    if ((L.friction >= 0) != had_friction) patterns_valid_ = false;
  }
  num_variables_ = extra;
  // One force scale for the scaled direction unknowns w = kappa t of all nodes.
  direction_scale_ = 0.0;
  for (size_t c = 0; c < layout_.size(); ++c)
    if (layout_[c].friction >= 0 && layout_[c].tangent_dim == 2)
      direction_scale_ = std::max(direction_scale_, bound_(static_cast<Eigen::Index>(c)));
  if (!(direction_scale_ > 0.0)) direction_scale_ = 1.0;
  equation_dofs_.clear();
  equation_row_.assign(static_cast<size_t>(n_), -1);
  for (int i = 0; i < n_; ++i) {
    if (row_kind_[static_cast<size_t>(i)] == 1) continue;
    equation_row_[static_cast<size_t>(i)] = static_cast<int>(equation_dofs_.size());
    equation_dofs_.push_back(i);
  }
  for (Layout& L : layout_)
    if (L.unit_row >= 0) L.unit_row += static_cast<int>(equation_dofs_.size());
  num_equations_ = static_cast<int>(equation_dofs_.size()) + num_unit_rows;
  pair_variable_.clear();
  for (const Layout& L : layout_) pair_variable_.push_back(L.slot[0]);
  for (const Layout& L : layout_) {
    if (L.friction < 0) continue;
    pair_variable_.push_back(L.slot[1]);                                 // du+
    pair_variable_.push_back(L.tangent_dim == 1 ? L.extra : L.slot[2]);  // du-
  }
  if (num_equations_ + static_cast<int>(pair_variable_.size()) != num_variables_)
    throw std::logic_error("ContactSystem: rows and unknowns do not match");
}

void ContactSystem::SetResidualScales(double force, double displacement) {
  if (!(force > 0.0) || !std::isfinite(force) || !(displacement > 0.0) ||
      !std::isfinite(displacement))
    throw std::invalid_argument(
        "contact::ContactSystem::SetResidualScales: the force and "
        "displacement scales must be finite and > 0, got " +
        std::to_string(force) + " and " + std::to_string(displacement));
  force_scale_ = force;
  displacement_scale_ = displacement;
}

bool ContactSystem::Scales(const ncp::Vector& z0, ncp::ResidualScales* scales) {
  if (!(force_scale_ > 0.0)) return false;
  // Round-off of the rows at the start point: |R(Sx + q)| is formed from terms of size
  // |q| + |S| |x|; a gap from gap0_c and x_n; a friction row from g_c and tau.
  LocalDisplacement(z0, &y_);
  const double eps = std::numeric_limits<double>::epsilon();
  const double y_max = y_.lpNorm<Eigen::Infinity>();
  const double bound_max = bound_.size() ? bound_.lpNorm<Eigen::Infinity>() : 0.0;
  const double force_floor =
      kRoundoffUlps * eps *
      (q_local_.lpNorm<Eigen::Infinity>() + s_row_sum_ * y_max + bound_max);
  const double slip_floor = kRoundoffUlps * eps * y_max;
  const Eigen::Index m = num_equations_, p = num_variables_ - num_equations_;
  const auto N = static_cast<Eigen::Index>(nodes_.size());
  scales->equation.setConstant(m, force_scale_);
  scales->equation_floor.setConstant(m, force_floor);
  // Pairs: (lambda_c, gap_c) for the nodes, then (slip part, friction force row) per
  // friction pair.
  scales->a.setConstant(p, displacement_scale_);
  scales->a_floor.setConstant(p, slip_floor);
  scales->b.setConstant(p, force_scale_);
  scales->b_floor.setConstant(p, force_floor);
  scales->a.head(N).setConstant(force_scale_);
  scales->a_floor.head(N).setConstant(force_floor);
  scales->b.head(N).setConstant(displacement_scale_);
  for (Eigen::Index c = 0; c < N; ++c)
    scales->b_floor(c) =
        kRoundoffUlps * eps *
        (std::abs(gap0_(c)) + std::abs(y_(layout_[static_cast<size_t>(c)].slot[0])));
  // The friction law of a node against its own bound g_c (tau + g_c >= 0, g_c - tau >=
  // 0).
  Eigen::Index pair = N;
  for (size_t c = 0; c < layout_.size(); ++c) {
    if (layout_[c].friction < 0) continue;
    scales->b(pair++) = bound_(static_cast<Eigen::Index>(c));
    scales->b(pair++) = bound_(static_cast<Eigen::Index>(c));
  }
  return true;
}

void ContactSystem::LocalDisplacement(const ncp::Vector& z, Eigen::VectorXd* y) const {
  *y = z.head(n_);
  for (const Layout& L : layout_) {
    if (L.friction < 0) continue;
    if (L.tangent_dim == 1) {
      (*y)(L.slot[1]) = z(L.slot[1]) - z(L.extra);  // y_t = du+ - du-   (eq. 89)
    } else {
      // y_T = (du+ - du-) (t1, t2) (eq. 67), with the direction stored as w = g_c t.
      const double slip_per_bound = (z(L.slot[1]) - z(L.slot[2])) / direction_scale_;
      (*y)(L.slot[1]) = slip_per_bound * z(L.extra + 1);
      (*y)(L.slot[2]) = slip_per_bound * z(L.extra + 2);
    }
  }
}

bool ContactSystem::Evaluate(const ncp::Vector& z, ncp::Vector* E, ncp::Vector* A,
                             ncp::Vector* B) {
  LocalDisplacement(z, &y_);
  r_.noalias() = S_local_ * y_;
  r_ += q_local_;
  // Equations: rows of R (S x + q) minus the friction force.
  for (size_t e = 0; e < equation_dofs_.size(); ++e)
    (*E)(static_cast<Eigen::Index>(e)) = r_(equation_dofs_[e]);
  Eigen::Index pair = static_cast<Eigen::Index>(nodes_.size());
  for (size_t c = 0; c < nodes_.size(); ++c) {
    const Layout& L = layout_[c];
    const int n_dof = L.slot[0];
    // Normal pair (thesis eq. 82, second row): reaction lambda = -(R(Sx+q))_n >= 0 and
    // gap = s - n.(u0 + x) >= 0.
    (*A)(static_cast<Eigen::Index>(c)) = -r_(n_dof);
    (*B)(static_cast<Eigen::Index>(c)) = gap0_(static_cast<Eigen::Index>(c)) - y_(n_dof);
    if (L.friction < 0) continue;
    const double g = bound_(static_cast<Eigen::Index>(c));
    if (L.tangent_dim == 1) {
      const double tau = z(L.extra + 1);
      (*E)(EquationRow(L.slot[1])) -= tau;  // r_t = tau              (eq. 90, third row)
      (*A)(pair) = z(L.slot[1]);            // (du+, tau + g)         (eq. 90, fourth row)
      (*B)(pair++) = tau + g;
      (*A)(pair) = z(L.extra);  // (du-, g - tau)         (eq. 90, fifth row)
      (*B)(pair++) = g - tau;
    } else {
      const double gt = z(L.extra), t1 = z(L.extra + 1) / direction_scale_,
                   t2 = z(L.extra + 2) / direction_scale_;
      (*E)(EquationRow(L.slot[1])) -= gt * t1;  // r_T = g (t1, t2)     (eq. 94, 66)
      (*E)(EquationRow(L.slot[2])) -= gt * t2;
      (*E)(L.unit_row) =
          direction_scale_ * (t1 * t1 + t2 * t2 - 1.0);  // eq. (59), force units
      (*A)(pair) = z(L.slot[1]);
      (*B)(pair++) = gt + g;
      (*A)(pair) = z(L.slot[2]);
      (*B)(pair++) = g - gt;
    }
  }
  return true;
}

template <typename Emit>
void ContactSystem::ForEachDisplacementDerivative(const ncp::Vector& z,
                                                  Emit&& emit) const {
  // D = dy/dz: identity on plain and normal slots, the slip split (eq. 89) or the slip
  // times the scaled direction (eq. 67) at friction nodes.
  for (int i = 0; i < n_; ++i)
    if (row_kind_[static_cast<size_t>(i)] != 2) emit(i, i, 1.0);
  for (const Layout& L : layout_) {
    if (L.friction < 0) continue;
    if (L.tangent_dim == 1) {
      emit(L.slot[1], L.slot[1], 1.0);
      emit(L.slot[1], L.extra, -1.0);
    } else {
      const double g = direction_scale_;
      const double slip = z(L.slot[1]) - z(L.slot[2]);
      for (int a = 1; a <= 2; ++a) {
        const double t = z(L.extra + a) / g;
        emit(L.slot[a], L.slot[1], t);
        emit(L.slot[a], L.slot[2], -t);
        emit(L.slot[a], L.extra + a, slip / g);
      }
    }
  }
}

template <typename Emit>
void ContactSystem::ForEachJacobianEntry(const ncp::Vector& z, Emit&& emit) const {
  auto copy_row = [&](int block, int out_row, int dof, double sign) {
    for (decltype(dr_)::InnerIterator it(dr_, dof); it; ++it)
      emit(block, out_row, static_cast<int>(it.col()), sign * it.value());
  };
  for (size_t e = 0; e < equation_dofs_.size(); ++e)
    copy_row(0, static_cast<int>(e), equation_dofs_[e], 1.0);
  int pair = static_cast<int>(nodes_.size());
  for (size_t c = 0; c < nodes_.size(); ++c) {
    const Layout& L = layout_[c];
    copy_row(1, static_cast<int>(c), L.slot[0], -1.0);  // d lambda / dz = -d r_n / dz
    emit(2, static_cast<int>(c), L.slot[0], -1.0);      // d gap / dz = -d y_n / dz
    if (L.friction < 0) continue;
    if (L.tangent_dim == 1) {
      const int tau = L.extra + 1;
      emit(0, static_cast<int>(EquationRow(L.slot[1])), tau, -1.0);
      emit(1, pair, L.slot[1], 1.0);
      emit(2, pair++, tau, 1.0);
      emit(1, pair, L.extra, 1.0);
      emit(2, pair++, tau, -1.0);
    } else {
      const int gv = L.extra;
      const double gt = z(gv), g = direction_scale_;
      for (int a = 1; a <= 2; ++a) {
        const int row = static_cast<int>(EquationRow(L.slot[a]));
        emit(0, row, gv, -z(gv + a) / g);                  // d(-gt w_a / kappa) / d gt
        emit(0, row, gv + a, -gt / g);                     // d(-gt w_a / kappa) / d w_a
        emit(0, L.unit_row, gv + a, 2.0 * z(gv + a) / g);  // d((w.w)/kappa - kappa)/dw_a
      }
      emit(1, pair, L.slot[1], 1.0);
      emit(2, pair++, gv, 1.0);
      emit(1, pair, L.slot[2], 1.0);
      emit(2, pair++, gv, -1.0);
    }
  }
}

void ContactSystem::BuildJacobianPatterns(const ncp::Vector& z) {
  std::vector<Triplet> entries;
  ForEachDisplacementDerivative(
      z, [&](int row, int col, double value) { entries.emplace_back(row, col, value); });
  BuildPattern(n_, num_variables_, entries, &D_, &d_position_);
  dr_ = S_local_ * D_;  // the structural product: Eigen keeps entries whose value is 0
  dr_row_.setZero(num_variables_);
  std::vector<Triplet> block_entries[3];
  ForEachJacobianEntry(z, [&](int block, int row, int col, double value) {
    block_entries[block].emplace_back(row, col, value);
  });
  const int p = num_variables_ - num_equations_;
  const Eigen::Index rows[3] = {num_equations_, p, p};
  for (int b = 0; b < 3; ++b)
    BuildPattern(rows[b], num_variables_, block_entries[b], &jacobian_pattern_[b],
                 &jacobian_position_[b]);
  patterns_valid_ = true;
}

bool ContactSystem::Jacobian(const ncp::Vector& z, ncp::SparseMatrix* JE,
                             ncp::SparseMatrix* JA, ncp::SparseMatrix* JB) {
  if (!patterns_valid_) BuildJacobianPatterns(z);
  // Values of D in place.
  double* d_values = D_.valuePtr();
  size_t k = 0;
  ForEachDisplacementDerivative(
      z, [&](int, int, double value) { d_values[d_position_[k++]] = value; });
  // dr = S_local D on its pattern: (S_local D)(i, :) = sum_j S_local(i, j) D(j, :),
  // summed into the dense dr_row_ (D has at most 3 entries per row), then gathered.
  for (Eigen::Index i = 0; i < n_; ++i) {
    for (decltype(S_local_)::InnerIterator s(S_local_, i); s; ++s)
      for (decltype(D_)::InnerIterator d(D_, s.col()); d; ++d)
        dr_row_(d.col()) += s.value() * d.value();
    for (decltype(dr_)::InnerIterator r(dr_, i); r; ++r) {
      r.valueRef() = dr_row_(r.col());
      dr_row_(r.col()) = 0.0;
    }
  }
  // JE, JA, JB: the caller's matrices take the pattern once (a copy that allocates only
  // if they do not have it yet), then the values are summed in place.
  ncp::SparseMatrix* out[3] = {JE, JA, JB};
  size_t next[3] = {0, 0, 0};
  for (int b = 0; b < 3; ++b) {
    if (!SamePattern(*out[b], jacobian_pattern_[b])) *out[b] = jacobian_pattern_[b];
    std::fill(out[b]->valuePtr(), out[b]->valuePtr() + out[b]->nonZeros(), 0.0);
  }
  ForEachJacobianEntry(z, [&](int block, int, int, double value) {
    const size_t b = static_cast<size_t>(block);
    out[b]->valuePtr()[jacobian_position_[b][next[b]++]] += value;
  });
  return true;
}

ncp::Vector ContactSystem::StartPoint(const Eigen::VectorXd& x_guess,
                                      const Eigen::MatrixXd& friction_guess) const {
  if (x_guess.size() != n_)
    throw std::invalid_argument("ContactSystem::StartPoint: guess has size " +
                                std::to_string(x_guess.size()) + ", expected " +
                                std::to_string(n_));
  const bool have_forces = friction_guess.size() > 0;
  if (have_forces && (friction_guess.rows() != dim_ - 1 ||
                      friction_guess.cols() != static_cast<Eigen::Index>(nodes_.size())))
    throw std::invalid_argument("ContactSystem::StartPoint: friction guess must be " +
                                std::to_string(dim_ - 1) + " x " +
                                std::to_string(nodes_.size()));
  ncp::Vector z = ncp::Vector::Zero(num_variables_);
  const Eigen::VectorXd y = rotation_ * x_guess;  // local components
  z.head(n_) = y;
  for (size_t c = 0; c < nodes_.size(); ++c) {
    const Layout& L = layout_[c];
    if (L.friction < 0) continue;
    const double g = bound_(static_cast<Eigen::Index>(c));
    if (L.tangent_dim == 1) {
      z(L.slot[1]) = std::max(y(L.slot[1]), 0.0);
      z(L.extra) = std::max(-y(L.slot[1]), 0.0);
      if (have_forces)
        z(L.extra + 1) =
            std::clamp(friction_guess(0, static_cast<Eigen::Index>(c)), -g, g);
      continue;
    }
    const Eigen::Vector2d slip(y(L.slot[1]), y(L.slot[2]));
    const Eigen::Vector2d force =
        have_forces
            ? Eigen::Vector2d(friction_guess.col(static_cast<Eigen::Index>(c)).head(2))
            : Eigen::Vector2d::Zero();
    Eigen::Vector2d t(1.0, 0.0);
    double magnitude = 0.5 * g;
    // A force guess that is round-off next to g (e.g. 1e-23 from a step without friction
    // at this node) would start with a near-zero magnitude: as singular as zero.
    if (force.norm() > 1e-3 * g) {
      t = force.normalized();
      magnitude = std::min(force.norm(), g);
    } else if (slip.norm() > 0.0) {
      t = slip.normalized();
      magnitude = -g;  // sliding along +t: the friction force is -g t
    }
    const double s = slip.dot(t);
    z(L.slot[1]) = std::max(s, 0.0);
    z(L.slot[2]) = std::max(-s, 0.0);
    z(L.extra) = magnitude;
    z(L.extra + 1) = direction_scale_ * t(0);
    z(L.extra + 2) = direction_scale_ * t(1);
  }
  return z;
}

ContactSystem::Result ContactSystem::Extract(const ncp::Vector& z) const {
  Result out;
  LocalDisplacement(z, &y_);
  r_.noalias() = S_local_ * y_;
  r_ += q_local_;
  const auto num_nodes = static_cast<Eigen::Index>(nodes_.size());
  out.normal_force.resize(num_nodes);
  out.gap.resize(num_nodes);
  out.tangent_force.setZero(dim_ - 1, num_nodes);
  out.slip.setZero(dim_ - 1, num_nodes);
  for (Eigen::Index c = 0; c < num_nodes; ++c) {
    const Layout& L = layout_[static_cast<size_t>(c)];
    out.normal_force(c) = -r_(L.slot[0]);
    out.gap(c) = gap0_(c) - y_(L.slot[0]);
    for (int a = 1; a < L.num_free; ++a) {
      out.tangent_force(a - 1, c) = r_(L.slot[a]);  // = tau at a solution (equation row)
      out.slip(a - 1, c) = y_(L.slot[a]);
    }
  }
  out.x = rotation_.transpose() * y_;  // back to the global frame
  return out;
}

}  // namespace contact
