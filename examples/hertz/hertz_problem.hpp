// The Hertz problem of hertz-example and contact-static-hertz-bench: a steel cylinder
// pressed onto a rigid plane (plane strain), meshed with the element size h at the
// contact.
//
// Hertz (Johnson, Contact Mechanics, 1985, section 4.3, eq. 4.43-4.45), cylinder of
// radius R on a rigid flat, load P per unit length, E* = E / (1 - nu^2):
//     a = sqrt(4 P R / (pi E*)),   p(x) = p0 sqrt(1 - x^2 / a^2),   p0 = 2 P / (pi a).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "contact/contact_boundary.hpp"
#include "contact/contact_frames.hpp"
#include "contact/dof_map.hpp"
#include "contact/elastic_body.hpp"
#include "contact/mesh_generation.hpp"
#include "contact/obstacle.hpp"
#include "contact/static_contact.hpp"

namespace hertz {

constexpr double kPi = 3.14159265358979323846;

// Data of the problem: steel, R = 50 mm, a load giving a = 0.02 R (small, so that the
// finite cylinder behaves like the half-space of the theory and the exact circular gap
// R - sqrt(R^2 - x^2) is the parabola x^2 / 2R to 1e-4).
struct HertzData {
  contact::IsotropicMaterial steel{210e9, 0.3, 7850.0};
  double R = 0.05;                              // [m]
  double E_star = 210e9 / (1.0 - 0.3 * 0.3);    // [Pa]
  double a = 0.02 * R;                          // half-width [m]
  double P = kPi * E_star * a * a / (4.0 * R);  // load per metre [N/m]
  double p0 = 2.0 * P / (kPi * a);              // peak pressure [Pa]
  double q = P / (2.0 * R);                     // pressure on the cut y = R [Pa]
  double Pressure(double x) const {
    return std::abs(x) >= a ? 0.0 : p0 * std::sqrt(1.0 - x * x / (a * a));
  }
};

struct Row {
  double h = 0, a = 0, p0 = 0, max_error = 0, seconds = 0;
  int dofs = 0, loaded = 0, newton_iterations = 0;
};

// One mesh: the quarter x >= 0 of the lower half of the cylinder, axis through (0, R),
// touching the floor y <= 0 at the origin. Symmetry u_x = 0 on x = 0 ("fixed"), the
// pressure q on the cut y = R ("load"), the arc up to x = 3a is Gamma_c ("contact").
class HertzProblem {
 public:
  // order 1: 3-node triangles; 2: 6-node triangles, the arc's mid-side nodes on the
  // circle.
  HertzProblem(const HertzData& data, int elements_per_half_width, int order = 1)
      : data_(data),
        order_(order),
        elements_per_a_(elements_per_half_width),
        h_(data.a / elements_per_half_width) {}

  // The row with the CPU time of mesh, assembly and solve [s].
  Row run(const std::filesystem::path& output_dir) {
    const std::clock_t start = std::clock();
    make_mesh();
    assemble();
    solve(DefaultOptions());
    const double seconds = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    Row row = write_output(output_dir);
    row.seconds = seconds;
    return row;
  }

  // The default settings, frictionless, with the tolerance absolute on the scaled system
  // (rows in metres): 1e-13 a.
  contact::StaticContactOptions DefaultOptions() const {
    contact::StaticContactOptions options;
    options.ncp.tolerance = 1e-13 * data_.a;
    return options;
  }

  // Element size h within 1.5 a of the origin,
  // growing with slope 1/4 to R / 8 (MakeQuarterDiskMesh).
  void make_mesh() {
    contact::QuarterDiskMeshOptions disk;
    disk.radius = data_.R;
    disk.contact_size = h_;
    disk.refined_radius = 1.5 * data_.a;
    disk.contact_extent = 3.0 * data_.a;
    disk.max_size = data_.R / 8.0;
    disk.order = order_;
    mesh_ = contact::MakeQuarterDiskMesh(disk);
  }

  // K and f on the free dofs, contact frames against the floor (normal -e_y, gap = y).
  void assemble() {
    const contact::ElasticBody body(mesh_, data_.steel);
    const contact::DofMap dofs = contact::MakeDofMap(
        mesh_, {contact::DirichletCondition{contact::kFixedGroup, {0}, {}}});
    const contact::ContactBoundary boundary = contact::MakeContactBoundary(body);
    frames_ = contact::MakeContactFrames(mesh_, boundary, dofs,
                                         contact::HalfSpace::ObstacleBelow(2, 1, 0.0),
                                         contact::NormalSource::kObstacle);
    const contact::SparseMatrix K = body.StiffnessMatrix();
    K_ = dofs.RestrictMatrix(K);
    f_ = dofs.RestrictLoad(K, body.TractionLoad(Eigen::Vector2d(0.0, -data_.q)));
  }

  // The static contact solve alone (what the benchmark times).
  const contact::StaticContactResult& solve(
      const contact::StaticContactOptions& options) {
    result_ = contact::SolveStaticContact(2, K_, f_, frames_.nodes, options);
    if (!result_.converged) std::cerr << "solve failed: " << result_.message << "\n";
    return result_;
  }

  // Pressure p_c = lambda_c / tributary area_c; a from the last two loaded nodes (p^2 is
  // linear in x^2 near the edge); p0 at the node x = 0.
  Row write_output(const std::filesystem::path& output_dir) {
    struct Sample {
      double x, p;
    };
    std::vector<Sample> profile;
    const double threshold = 1e-9 * result_.normal_force.maxCoeff();
    for (size_t c = 0; c < frames_.nodes.size(); ++c) {
      const double lambda = result_.normal_force(static_cast<Eigen::Index>(c));
      profile.push_back({mesh_.nodes(0, frames_.nodes[c].node),
                         lambda > threshold ? lambda / frames_.nodes[c].area : 0.0});
    }
    std::sort(profile.begin(), profile.end(),
              [](const Sample& s, const Sample& t) { return s.x < t.x; });
    Row row;
    row.h = h_;
    row.dofs = static_cast<int>(K_.rows());
    row.newton_iterations = result_.newton_iterations;
    row.p0 = profile.front().p;
    size_t last = 0;
    while (last + 1 < profile.size() && profile[last + 1].p > 0.0) ++last;
    row.loaded = static_cast<int>(last) + 1;
    const double x1 = profile[last - 1].x, p1 = profile[last - 1].p;
    const double x2 = profile[last].x, p2 = profile[last].p;
    row.a = std::sqrt(x2 * x2 + p2 * p2 * (x2 * x2 - x1 * x1) / (p1 * p1 - p2 * p2));
    std::ofstream csv(output_dir /
                      ("hertz_pressure_a_over_h_" + std::to_string(elements_per_a_) +
                       (order_ == 2 ? "_order2" : "") + ".csv"));
    csv << "x_m,x_over_a,p_computed_Pa,p_exact_Pa\n";
    csv.precision(10);
    for (const Sample& s : profile) {
      csv << s.x << "," << s.x / data_.a << "," << s.p << "," << data_.Pressure(s.x)
          << "\n";
      row.max_error =
          std::max(row.max_error, std::abs(s.p - data_.Pressure(s.x)) / data_.p0);
    }
    return row;
  }

  const contact::Mesh& mesh() const { return mesh_; }
  const contact::ContactFrames& frames() const { return frames_; }
  const contact::SparseMatrix& stiffness() const { return K_; }
  double h() const { return h_; }

 private:
  HertzData data_;
  int order_;
  int elements_per_a_;
  double h_;
  contact::Mesh mesh_;
  contact::ContactFrames frames_;
  contact::SparseMatrix K_;
  contact::Vector f_;
  contact::StaticContactResult result_;
};

}  // namespace hertz
