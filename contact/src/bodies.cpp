#include "contact/bodies.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

namespace contact {
namespace {

void CheckBodies(const std::vector<Body>& bodies) {
  if (bodies.empty())
    throw std::invalid_argument("contact::AssembleBodies: no bodies (need at least one)");
  std::set<std::string> names;
  const Body& first = bodies.front();
  for (const Body& b : bodies) {
    if (b.name.empty())
      throw std::invalid_argument("contact::AssembleBodies: a body has an empty name");
    if (!names.insert(b.name).second)
      throw std::invalid_argument("contact::AssembleBodies: two bodies are named '" +
                                  b.name + "' (names must be unique)");
    if (b.body.dim() != first.body.dim())
      throw std::invalid_argument(
          "contact::AssembleBodies: body '" + b.name + "' is " +
          std::to_string(b.body.dim()) + "D but body '" + first.name + "' is " +
          std::to_string(first.body.dim()) + "D (all bodies need one dimension)");
    if (b.body.dim() == 2 && b.body.IntegrationFactor() != first.body.IntegrationFactor())
      throw std::invalid_argument(
          "contact::AssembleBodies: body '" + b.name + "' has thickness " +
          std::to_string(b.body.IntegrationFactor()) + " m but body '" + first.name +
          "' has " + std::to_string(first.body.IntegrationFactor()) +
          " m (2D bodies in contact need one thickness)");
  }
}

/// diag(blocks) with blocks[b] placed at rows and columns offset[b].
SparseMatrix BlockDiagonal(const std::vector<SparseMatrix>& blocks,
                           const std::vector<int>& offset) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (size_t b = 0; b < blocks.size(); ++b)
    for (int col = 0; col < blocks[b].outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(blocks[b], col); it; ++it)
        triplets.emplace_back(offset[b] + static_cast<int>(it.row()),
                              offset[b] + static_cast<int>(it.col()), it.value());
  SparseMatrix A(offset.back(), offset.back());
  A.setFromTriplets(triplets.begin(), triplets.end());
  return A;
}

}  // namespace

Vector BodySystem::BodyPart(const Vector& global, int body) const {
  const int begin = offset[static_cast<size_t>(body)];
  return global.segment(begin, offset[static_cast<size_t>(body) + 1] - begin);
}

BodySystem AssembleBodies(const std::vector<Body>& bodies) {
  CheckBodies(bodies);
  BodySystem system;
  system.dim = bodies.front().body.dim();
  system.offset.push_back(0);
  for (const Body& b : bodies)
    system.offset.push_back(system.offset.back() + b.body.NumDofs());
  std::vector<SparseMatrix> K, M;
  system.lumped_mass.resize(system.NumDofs());
  std::vector<int> constrained;
  Vector prescribed = Vector::Zero(system.NumDofs());
  for (size_t b = 0; b < bodies.size(); ++b) {
    const ElasticBody& body = bodies[b].body;
    const int begin = system.offset[b];
    K.push_back(body.StiffnessMatrix());
    M.push_back(body.ConsistentMassMatrix());
    system.lumped_mass.segment(begin, body.NumDofs()) = body.LumpedMass();
    DofMap own;
    try {
      own = MakeDofMap(body.mesh(), bodies[b].dirichlet);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("body '" + bodies[b].name + "': " + e.what());
    }
    for (int dof : own.ConstrainedDofs()) {
      constrained.push_back(begin + dof);
      prescribed(begin + dof) = own.PrescribedValues()(dof);
    }
  }
  system.stiffness = BlockDiagonal(K, system.offset);
  system.mass = BlockDiagonal(M, system.offset);
  system.dofs = DofMap(system.NumDofs(), constrained, prescribed);
  return system;
}

int FindBody(const std::vector<Body>& bodies, const std::string& name) {
  std::string known;
  for (size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b].name == name) return static_cast<int>(b);
    known += (b ? ", '" : "'") + bodies[b].name + "'";
  }
  throw std::invalid_argument("no body named '" + name + "' (bodies: " + known + ")");
}

}  // namespace contact
