#include "quadratic_element.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace contact::internal {
namespace {

using Corners = std::vector<std::vector<int>>;

// A value with its first derivatives with respect to xi_0 .. xi_2.
struct Jet {
  double v = 0;
  std::array<double, 3> d{0, 0, 0};
};
Jet operator+(Jet a, const Jet& b) {
  a.v += b.v;
  for (int k = 0; k < 3; ++k) a.d[k] += b.d[k];
  return a;
}
Jet operator*(const Jet& a, const Jet& b) {
  Jet r;
  r.v = a.v * b.v;
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return r;
}
Jet operator*(double s, Jet a) {
  a.v *= s;
  for (int k = 0; k < 3; ++k) a.d[k] *= s;
  return a;
}
Jet operator+(double s, Jet a) {
  a.v += s;
  return a;
}
Jet Variable(double value, int k) {
  Jet j;
  j.v = value;
  j.d[static_cast<size_t>(k)] = 1;
  return j;
}

Corners Singles(int n) {
  Corners c;
  for (int a = 0; a < n; ++a) c.push_back({a});
  return c;
}
Corners Append(Corners c, const Corners& more) {
  c.insert(c.end(), more.begin(), more.end());
  return c;
}

enum class Family { kSimplex, kLagrange, kSerendipity };

struct Layout {
  Family family;
  int corners;
  const Corners* node_corners;
};

// gmsh's node orders (mesh.hpp).
const Layout* FindLayout(int ref_dim, int nodes) {
  static const Corners line3 = Append(Singles(2), {{0, 1}});
  static const Corners tri6 = Append(Singles(3), {{0, 1}, {1, 2}, {2, 0}});
  static const Corners quad8 = Append(Singles(4), {{0, 1}, {1, 2}, {2, 3}, {3, 0}});
  static const Corners quad9 = Append(quad8, {{0, 1, 2, 3}});
  static const Corners tet10 =
      Append(Singles(4), {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}});
  static const Corners hex20 = Append(Singles(8), {{0, 1},
                                                   {0, 3},
                                                   {0, 4},
                                                   {1, 2},
                                                   {1, 5},
                                                   {2, 3},
                                                   {2, 6},
                                                   {3, 7},
                                                   {4, 5},
                                                   {4, 7},
                                                   {5, 6},
                                                   {6, 7}});
  static const Corners hex27 = Append(hex20, {{0, 1, 2, 3},
                                              {0, 1, 5, 4},
                                              {0, 3, 7, 4},
                                              {1, 2, 6, 5},
                                              {2, 3, 7, 6},
                                              {4, 5, 6, 7},
                                              {0, 1, 2, 3, 4, 5, 6, 7}});
  static const Layout layouts[] = {
      {Family::kLagrange, 2, &line3},    {Family::kSimplex, 3, &tri6},
      {Family::kSerendipity, 4, &quad8}, {Family::kLagrange, 4, &quad9},
      {Family::kSimplex, 4, &tet10},     {Family::kSerendipity, 8, &hex20},
      {Family::kLagrange, 8, &hex27}};
  for (const Layout& layout : layouts) {
    const int dim = layout.family == Family::kSimplex ? layout.corners - 1
                    : layout.corners == 2             ? 1
                    : layout.corners == 4             ? 2
                                                      : 3;
    if (dim == ref_dim && static_cast<int>(layout.node_corners->size()) == nodes)
      return &layout;
  }
  return nullptr;
}

// Reference coordinates of corner a: simplex vertex (0 or unit vector), or a corner of
// [-1, 1]^d in gmsh order (bits: x, y alternate around the bottom face, z = a >= 4).
void CornerPosition(Family family, int dim, int a, double* x) {
  if (family == Family::kSimplex) {
    for (int k = 0; k < dim; ++k) x[k] = (a == k + 1) ? 1.0 : 0.0;
    return;
  }
  static constexpr double kSquare[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  if (dim == 1) {
    x[0] = a == 0 ? -1.0 : 1.0;
    return;
  }
  x[0] = kSquare[a % 4][0];
  x[1] = kSquare[a % 4][1];
  if (dim == 3) x[2] = a >= 4 ? 1.0 : -1.0;
}

Jet Lagrange1D(double c, const Jet& t) {
  if (c < -0.5) return 0.5 * (t * (-1.0 + t));
  if (c > 0.5) return 0.5 * (t * (1.0 + t));
  return 1.0 + (-1.0) * (t * t);
}

Jet ShapeFunction(const Layout& layout, int dim, int a, const double* c, const Jet* xi) {
  const std::vector<int>& corners = (*layout.node_corners)[static_cast<size_t>(a)];
  if (layout.family == Family::kSimplex) {
    auto barycentric = [&](int i) {
      if (i > 0) return xi[i - 1];
      Jet l0;
      l0.v = 1;
      for (int k = 0; k < dim; ++k) l0 = l0 + (-1.0) * xi[k];
      return l0;
    };
    if (corners.size() == 1) {
      const Jet L = barycentric(corners[0]);
      return L * (-1.0 + 2.0 * L);
    }
    return 4.0 * (barycentric(corners[0]) * barycentric(corners[1]));
  }
  Jet N;
  N.v = 1;
  if (layout.family == Family::kLagrange) {
    for (int k = 0; k < dim; ++k) N = N * Lagrange1D(c[k], xi[k]);
    return N;
  }
  // Serendipity.
  if (corners.size() == 1) {
    Jet sum;
    sum.v = 1.0 - dim;
    for (int k = 0; k < dim; ++k) {
      N = N * (0.5 * (1.0 + c[k] * xi[k]));
      sum = sum + c[k] * xi[k];
    }
    return N * sum;
  }
  for (int k = 0; k < dim; ++k)
    N = N * (c[k] == 0 ? 1.0 + (-1.0) * (xi[k] * xi[k]) : 0.5 * (1.0 + c[k] * xi[k]));
  return N;
}

}  // namespace

const std::vector<std::vector<int>>& NodeCorners(int ref_dim, int nodes) {
  static const Corners none;
  const Layout* layout = FindLayout(ref_dim, nodes);
  return layout ? *layout->node_corners : none;
}

std::vector<double> ReferenceNodes(int ref_dim, int nodes) {
  std::vector<double> x(static_cast<size_t>(ref_dim * nodes), 0.0);
  const Layout* layout = FindLayout(ref_dim, nodes);
  const bool simplex =
      layout ? layout->family == Family::kSimplex : nodes == ref_dim + 1 && ref_dim > 1;
  const Family family = simplex ? Family::kSimplex : Family::kLagrange;
  for (int a = 0; a < nodes; ++a) {
    const std::vector<int> corners =
        layout ? (*layout->node_corners)[static_cast<size_t>(a)] : std::vector<int>{a};
    for (const int corner : corners) {
      double p[3];
      CornerPosition(family, ref_dim, corner, p);
      for (int k = 0; k < ref_dim; ++k)
        x[static_cast<size_t>(ref_dim * a + k)] += p[k] / corners.size();
    }
  }
  return x;
}

bool EvaluateQuadraticShape(int ref_dim, int nodes, const double* xi, double* N,
                            double* dN_dxi) {
  const Layout* layout = FindLayout(ref_dim, nodes);
  if (!layout) return false;
  const std::vector<double> c = ReferenceNodes(ref_dim, nodes);
  Jet x[3];
  for (int k = 0; k < ref_dim; ++k) x[k] = Variable(xi[k], k);
  for (int a = 0; a < nodes; ++a) {
    const Jet value =
        ShapeFunction(*layout, ref_dim, a, &c[static_cast<size_t>(ref_dim * a)], x);
    N[a] = value.v;
    for (int k = 0; k < ref_dim; ++k)
      dN_dxi[ref_dim * a + k] = value.d[static_cast<size_t>(k)];
  }
  return true;
}

std::vector<int> ExtendCornerPermutation(int ref_dim, int nodes,
                                         const std::vector<int>& corner_map) {
  const Corners& corners = NodeCorners(ref_dim, nodes);
  if (corners.empty()) return corner_map;
  auto sorted = [](std::vector<int> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  std::vector<int> result(static_cast<size_t>(nodes), -1);
  for (int a = 0; a < nodes; ++a) {
    std::vector<int> image;
    for (const int corner : corners[static_cast<size_t>(a)])
      image.push_back(corner_map[static_cast<size_t>(corner)]);
    image = sorted(image);
    for (int b = 0; b < nodes; ++b)
      if (sorted(corners[static_cast<size_t>(b)]) == image)
        result[static_cast<size_t>(a)] = b;
    if (result[static_cast<size_t>(a)] < 0)
      throw std::logic_error(
          "ExtendCornerPermutation: corner map is not a symmetry of the "
          "reference element with " +
          std::to_string(nodes) + " nodes");
  }
  return result;
}

}  // namespace contact::internal
