// Published complementarity problems of MCPLIB (S. P. Dirkse and M. C. Ferris, "MCPLIB: a
// collection of nonlinear mixed complementarity problems", Optim. Methods Softw. 5 (1995)
// 319-345) and of the GAMS model library. Every formula and data table below is written
// out from the file named above it (the mathematics and data are transcribed, no code is
// copied); each Jacobian is the analytic derivative of the lines above it.
//
// Convention of the GAMS MCP files: an equation "lhs =g= rhs" matched with a positive
// variable v gives the pair  v >= lo  perp  F_v = lhs - rhs >= 0; a variable fixed with
// .fx is removed together with the equation matched to it.
#include "ncp_collection/mcplib_nlp.hpp"

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dense_function.hpp"
#include "ncp_collection/affine_function.hpp"
#include "problem_building.hpp"

namespace ncp::collection {
namespace {

using internal::kInf;
using internal::MakeStandardNcp;
using internal::Vec;

// A function written on a "full" variable vector z of which some components are fixed
// (GAMS .fx): the fixed components and the equations matched to them are removed.
class FullModel {
 public:
  virtual ~FullModel() = default;
  virtual int FullSize() const = 0;
  // F(z) and, if J is not null, dF/dz (FullSize x FullSize, zeroed on entry).
  virtual bool Eval(const Vector& z, Vector* F, DenseMatrix* J) const = 0;
};

class ReducedFunction : public internal::DenseJacobianFunction {
 public:
  // fixed: (index in z, value) pairs.
  ReducedFunction(std::unique_ptr<FullModel> model,
                  const std::vector<std::pair<int, double>>& fixed)
      : DenseJacobianFunction(model->FullSize() - static_cast<int>(fixed.size())),
        model_(std::move(model)),
        z_(Vector::Zero(model_->FullSize())),
        Fz_(model_->FullSize()),
        Jz_(model_->FullSize(), model_->FullSize()) {
    std::vector<bool> is_fixed(static_cast<size_t>(model_->FullSize()), false);
    for (const auto& [index, value] : fixed) {
      is_fixed[static_cast<size_t>(index)] = true;
      z_(index) = value;
    }
    for (int i = 0; i < model_->FullSize(); ++i)
      if (!is_fixed[static_cast<size_t>(i)]) free_.push_back(i);
  }
  bool Evaluate(const Vector& x, Vector* F) override {
    Fill(x);
    if (!model_->Eval(z_, &Fz_, nullptr)) return false;
    for (size_t k = 0; k < free_.size(); ++k)
      (*F)(static_cast<Eigen::Index>(k)) = Fz_(free_[k]);
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& x, DenseMatrix* J) override {
    Fill(x);
    Jz_.setZero();
    if (!model_->Eval(z_, &Fz_, &Jz_)) return false;
    for (size_t r = 0; r < free_.size(); ++r)
      for (size_t c = 0; c < free_.size(); ++c)
        (*J)(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
            Jz_(free_[r], free_[c]);
    return true;
  }

 private:
  void Fill(const Vector& x) {
    for (size_t k = 0; k < free_.size(); ++k)
      z_(free_[k]) = x(static_cast<Eigen::Index>(k));
  }
  std::unique_ptr<FullModel> model_;
  std::vector<int> free_;
  Vector z_, Fz_;
  DenseMatrix Jz_;
};

// ---- Colville's second test problem ------------------------------------------------
// A. R. Colville, "A comparative study on nonlinear programming codes", IBM New York
// Scientific Center Report 320-2949 (1968), test problem 2; W. Hock and K. Schittkowski,
// "Test examples for nonlinear programming codes", Lecture Notes in Econ. and Math.
// Systems 187 (1981), problem 117 (the dual form). Data read from GAMS-dev/gamsworld,
// PrincetonLib/Hock and Schittkowski Suite/Indexed_models/hs117.gms, and checked against
// JuliaSmoothOptimizers/OptimizationProblems.jl, src/hs117.jl (same a, b, c, d, e):
//   HS117:  min_{v in R^10, w in R^5}  -b'v + w'Cw + 2 sum_j d_j w_j^3
//           s.t. g_j = 2 (Cw)_j + 3 d_j w_j^2 + e_j - (A'v)_j >= 0 (j = 1..5), v, w >= 0,
// with A = (a_kj) 10 x 5 and C symmetric. HS117 is the Wolfe dual of the primal
//   min_{w >= 0}  e'w + w'Cw + sum_j d_j w_j^3   s.t.  A w >= b  (10 constraints),
// whose multipliers are v; conversely the multipliers u of HS117's g are w. Published
// optimum of HS117: f* = 32.34867897 at v* = (0, 0, 5.174136, 0, 3.061093, 11.83968, 0,
// 0, 0.1039071, 0), w* = (0.2999929, 0.3334709, 0.3999910, 0.4283145, 0.2239607).
constexpr double kColA[10][5] = {
    {-16, 2, 0, 1, 0},    {0, -2, 0, 4, 2}, {-3.5, 0, 2, 0, 0},   {0, -2, 0, -4, -1},
    {0, -9, -2, 1, -2.8}, {2, 0, -4, 0, 0}, {-1, -1, -1, -1, -1}, {-1, -2, -3, -2, -1},
    {1, 2, 3, 4, 5},      {1, 1, 1, 1, 1}};
constexpr double kColB[10] = {-40, -2, -0.25, -4, -4, -1, -40, -60, 5, 1};
constexpr double kColC[5][5] = {{30, -20, -10, 32, -10},
                                {-20, 39, -6, -31, 32},
                                {-10, -6, 10, -6, -10},
                                {32, -31, -6, 39, -20},
                                {-10, 32, -10, -20, 30}};
constexpr double kColD[5] = {4, 8, 10, 6, 2};
constexpr double kColE[5] = {-15, -27, -36, -18, -12};

// colvdual: z = (v (10), w (5), u (5)), L = f - u'g:
//   F_v_k = dL/dv_k = -b_k + sum_j a_kj u_j                                     perp v_k
//   >= 0 F_w_i = dL/dw_i = 2 (Cw)_i + 6 d_i w_i^2 - 2 (Cu)_i - 6 d_i w_i u_i perp w_i >=
//   0 F_u_j = g_j     = 2 (Cw)_j + 3 d_j w_j^2 + e_j - sum_k a_kj v_k              perp
//   u_j >= 0
class ColvilleDualFunction : public internal::DenseJacobianFunction {
 public:
  ColvilleDualFunction() : DenseJacobianFunction(20) {}
  bool Evaluate(const Vector& z, Vector* F) override {
    for (int k = 0; k < 10; ++k) {
      double s = -kColB[k];
      for (int j = 0; j < 5; ++j) s += kColA[k][j] * z(15 + j);
      (*F)(k) = s;
    }
    for (int i = 0; i < 5; ++i) {
      const double w = z(10 + i), u = z(15 + i);
      double cw = 0, cu = 0;
      for (int m = 0; m < 5; ++m) {
        cw += kColC[i][m] * z(10 + m);
        cu += kColC[i][m] * z(15 + m);
      }
      (*F)(10 + i) = 2 * cw + 6 * kColD[i] * w * w - 2 * cu - 6 * kColD[i] * w * u;
      double av = 0;
      for (int k = 0; k < 10; ++k) av += kColA[k][i] * z(k);
      (*F)(15 + i) = 2 * cw + 3 * kColD[i] * w * w + kColE[i] - av;
    }
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& z, DenseMatrix* J) override {
    for (int k = 0; k < 10; ++k)
      for (int j = 0; j < 5; ++j) {
        (*J)(k, 15 + j) = kColA[k][j];
        (*J)(15 + j, k) = -kColA[k][j];
      }
    for (int i = 0; i < 5; ++i) {
      const double w = z(10 + i), u = z(15 + i);
      for (int m = 0; m < 5; ++m) {
        (*J)(10 + i, 10 + m) = 2 * kColC[i][m];
        (*J)(10 + i, 15 + m) = -2 * kColC[i][m];
        (*J)(15 + i, 10 + m) = 2 * kColC[i][m];
      }
      (*J)(10 + i, 10 + i) += 12 * kColD[i] * w - 6 * kColD[i] * u;
      (*J)(10 + i, 15 + i) += -6 * kColD[i] * w;
      (*J)(15 + i, 10 + i) += 6 * kColD[i] * w;
    }
    return true;
  }
};

// colvnlp: z = (w (5), lambda (10)), L = e'w + w'Cw + d'w^3 - lambda'(Aw - b):
//   F_w_j      = e_j + 2 (Cw)_j + 3 d_j w_j^2 - sum_k a_kj lambda_k     perp w_j >= 0
//   F_lambda_k = sum_j a_kj w_j - b_k                                   perp lambda_k >=
//   0
class ColvilleNlpFunction : public internal::DenseJacobianFunction {
 public:
  ColvilleNlpFunction() : DenseJacobianFunction(15) {}
  bool Evaluate(const Vector& z, Vector* F) override {
    for (int j = 0; j < 5; ++j) {
      double s = kColE[j] + 3 * kColD[j] * z(j) * z(j);
      for (int m = 0; m < 5; ++m) s += 2 * kColC[j][m] * z(m);
      for (int k = 0; k < 10; ++k) s -= kColA[k][j] * z(5 + k);
      (*F)(j) = s;
    }
    for (int k = 0; k < 10; ++k) {
      double s = -kColB[k];
      for (int j = 0; j < 5; ++j) s += kColA[k][j] * z(j);
      (*F)(5 + k) = s;
    }
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& z, DenseMatrix* J) override {
    for (int j = 0; j < 5; ++j) {
      for (int m = 0; m < 5; ++m) (*J)(j, m) = 2 * kColC[j][m];
      (*J)(j, j) += 6 * kColD[j] * z(j);
      for (int k = 0; k < 10; ++k) {
        (*J)(j, 5 + k) = -kColA[k][j];
        (*J)(5 + k, j) = kColA[k][j];
      }
    }
    return true;
  }
};

// HS117's standard start: v = w = 0.001 except v_7 = 60.
Vector Hs117Start() {
  Vector x = Vector::Constant(15, 0.001);
  x(6) = 60.0;
  return x;
}

// ---- Activity analysis general equilibrium (scarfmcp, hansmcp) ----------------------
// The model of GAMS model library scarfmcp.gms (SEQ=132) and hansmcp.gms (SEQ=135), from
// H. Scarf and T. Hansen, "The Computation of Economic Equilibria", Yale Univ. Press
// (1973). Commodities c, sectors s, consumers h; z = (p (prices), y (activity levels),
// i (incomes)); a(c,s) = output - input of the activity analysis matrix, e(c,h)
// endowments, alpha(c,h) = d(c,h) / sum_c' d(c',h) demand shares of the reference
// demands d, esub(h) demand elasticities:
//   F_p_c = sum_s a(c,s) y_s + sum_h e(c,h) - sum_h D(c,h)      perp p_c >= plo_c   (mkt)
//   F_y_s = -sum_c a(c,s) p_c                                   perp y_s >= 0 (profit)
//   F_i_h = i_h - sum_c p_c e(c,h)                              perp i_h >= 0 (income)
// with the CES demand (GAMS writes esub = 1, Cobb-Douglas, separately; it is the same
// formula, as S_h = sum_c alpha = 1 then)
//   D(c,h) = i_h alpha(c,h) p_c^(-esub_h) / S_h,   S_h = sum_c alpha(c,h) p_c^(1-esub_h).
// plo_c = 1e-5 for the commodities some consumer demands (alpha > 0), else 0, as in the
// .gms files. Evaluate() returns false if such a price is <= 0.
class ActivityAnalysisModel : public FullModel {
 public:
  ActivityAnalysisModel(DenseMatrix a, DenseMatrix e, DenseMatrix reference_demand,
                        Vector esub)
      : a_(std::move(a)), e_(std::move(e)), esub_(std::move(esub)) {
    alpha_ = reference_demand;
    for (Eigen::Index h = 0; h < alpha_.cols(); ++h)
      alpha_.col(h) /= reference_demand.col(h).sum();
  }
  int NumCommodities() const { return static_cast<int>(a_.rows()); }
  int NumSectors() const { return static_cast<int>(a_.cols()); }
  int NumConsumers() const { return static_cast<int>(e_.cols()); }
  int FullSize() const override {
    return NumCommodities() + NumSectors() + NumConsumers();
  }
  bool Demanded(int c) const { return alpha_.row(c).maxCoeff() > 0.0; }

  bool Eval(const Vector& z, Vector* F, DenseMatrix* J) const override {
    const int nc = NumCommodities(), ns = NumSectors(), nh = NumConsumers();
    const int Y0 = nc, I0 = nc + ns;
    const Vector p = z.head(nc), y = z.segment(Y0, ns), inc = z.tail(nh);
    for (int c = 0; c < nc; ++c)
      if (Demanded(c) && !(p(c) > 0.0)) return false;
    // F_p = a y + sum_h e - D;  F_y = -a' p;  F_i = i - e' p.
    F->head(nc) = a_ * y + e_.rowwise().sum();
    F->segment(Y0, ns) = -a_.transpose() * p;
    F->tail(nh) = inc - e_.transpose() * p;
    if (J) {
      J->block(0, Y0, nc, ns) = a_;
      J->block(Y0, 0, ns, nc) = -a_.transpose();
      J->block(I0, 0, nh, nc) = -e_.transpose();
      J->block(I0, I0, nh, nh) = DenseMatrix::Identity(nh, nh);
    }
    for (int h = 0; h < nh; ++h) {
      const double sigma = esub_(h);
      double S = 0.0;
      for (int c = 0; c < nc; ++c)
        if (alpha_(c, h) > 0.0) S += alpha_(c, h) * std::pow(p(c), 1.0 - sigma);
      for (int c = 0; c < nc; ++c) {
        if (!(alpha_(c, h) > 0.0)) continue;
        const double pc_ms = std::pow(p(c), -sigma);
        const double D = inc(h) * alpha_(c, h) * pc_ms / S;
        (*F)(c) -= D;
        if (!J) continue;
        // dD/di_h = alpha p_c^-sigma / S
        (*J)(c, I0 + h) -= alpha_(c, h) * pc_ms / S;
        // dD/dp_c (own) = -sigma D / p_c;  dD/dp_k = -D (1 - sigma) alpha_kh p_k^-sigma /
        // S
        (*J)(c, c) -= -sigma * D / p(c);
        for (int k = 0; k < nc; ++k) {
          if (!(alpha_(k, h) > 0.0)) continue;
          (*J)(c, k) -= -D * (1.0 - sigma) * alpha_(k, h) * std::pow(p(k), -sigma) / S;
        }
      }
    }
    return true;
  }

 private:
  DenseMatrix a_, e_, alpha_;
  Vector esub_;
};

DenseMatrix Rows(int rows, int cols, std::initializer_list<double> values) {
  DenseMatrix M(rows, cols);
  auto it = values.begin();
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) M(r, c) = *it++;
  return M;
}

// ---- Shoven-Whalley 2 x 2 x 2 model (two3mcp) ----------------------------------------
// GAMS model library two3mcp.gms (SEQ=131), model jel, from J. Shoven and J. Whalley,
// "Applied general equilibrium models of taxation and international trade", J. Econ.
// Literature 22 (1984) 1007-1051; the reference case (no taxes). Factors f (labor,
// capital), sectors s (mfrs, nonmfrs), households h (rich, poor); z = (W (2), P (2),
// Y (2), I (2)). CES unit cost and unit factor demand of sector s:
//   c_s(W) = Q_s^(1/(1-sigma_s)) / phi_s,   Q_s = sum_f delta_fs^sigma_s W_f^(1-sigma_s),
//   x_fs(W) = phi_s^(sigma_s-1) (delta_fs c_s / W_f)^sigma_s   (= dc_s/dW_f),
//   F_W_f = sum_h e_fh - sum_s Y_s x_fs(W)                          perp W_f >= 1e-4
//   (fmkt) F_P_s = Y_s - sum_h I_h alpha_sh P_s^-sc_h / sum_s' alpha_s'h P_s'^(1-sc_h)
//                                                                   perp P_s >= 1e-4
//                                                                   (cmkt)
//   F_Y_s = c_s(W) - P_s                                            perp Y_s >= 0
//   (profit) F_I_h = I_h - sum_f e_fh W_f                                    perp I_h >=
//   0  (income)
// Data: sc = (1.5, 0.75), alpha = [0.5 0.3; 0.5 0.7], e = [0 60; 25 0] (rows labor,
// capital), phi = (1.5, 2), delta = [0.6 0.7; 0.4 0.3], sigma = (2, 0.5). W_labor = 1 is
// fixed (numeraire).
class Two3Model : public FullModel {
 public:
  int FullSize() const override { return 8; }
  bool Eval(const Vector& z, Vector* F, DenseMatrix* J) const override {
    const double* W = z.data();
    const double* P = z.data() + 2;
    const double* Y = z.data() + 4;
    const double* I = z.data() + 6;
    for (int k = 0; k < 4; ++k)
      if (!(z(k) > 0.0)) return false;
    for (int f = 0; f < 2; ++f) (*F)(f) = kE[f][0] + kE[f][1];
    for (int s = 0; s < 2; ++s) {
      const double sg = kSigma[s];
      double Q = 0;
      for (int f = 0; f < 2; ++f)
        Q += std::pow(kDelta[f][s], sg) * std::pow(W[f], 1 - sg);
      const double c = std::pow(Q, 1 / (1 - sg)) / kPhi[s];
      // dc/dW_g = x_gs
      double x[2];
      for (int f = 0; f < 2; ++f)
        x[f] = std::pow(kPhi[s], sg - 1) * std::pow(kDelta[f][s] * c / W[f], sg);
      for (int f = 0; f < 2; ++f) (*F)(f) -= Y[s] * x[f];
      (*F)(4 + s) = c - P[s];
      if (J) {
        for (int f = 0; f < 2; ++f) {
          (*J)(f, 4 + s) -= x[f];
          // dx_f/dW_g = sigma x_f (x_g / c - delta_fg / W_f)
          for (int g = 0; g < 2; ++g)
            (*J)(f, g) -= Y[s] * sg * x[f] * (x[g] / c - (f == g ? 1.0 / W[f] : 0.0));
          (*J)(4 + s, f) = x[f];
        }
        (*J)(4 + s, 2 + s) = -1;
      }
    }
    for (int s = 0; s < 2; ++s) {
      (*F)(2 + s) = Y[s];
      if (J) (*J)(2 + s, 4 + s) = 1;
    }
    for (int h = 0; h < 2; ++h) {
      const double sc = kSigmaC[h];
      double S = 0;
      for (int s = 0; s < 2; ++s) S += kAlpha[s][h] * std::pow(P[s], 1 - sc);
      for (int s = 0; s < 2; ++s) {
        const double ps = std::pow(P[s], -sc);
        const double D = I[h] * kAlpha[s][h] * ps / S;
        (*F)(2 + s) -= D;
        if (!J) continue;
        (*J)(2 + s, 6 + h) -= kAlpha[s][h] * ps / S;
        (*J)(2 + s, 2 + s) -= -sc * D / P[s];
        for (int k = 0; k < 2; ++k)
          (*J)(2 + s, 2 + k) -= -D * (1 - sc) * kAlpha[k][h] * std::pow(P[k], -sc) / S;
      }
      (*F)(6 + h) = I[h] - kE[0][h] * W[0] - kE[1][h] * W[1];
      if (J) {
        (*J)(6 + h, 6 + h) = 1;
        (*J)(6 + h, 0) = -kE[0][h];
        (*J)(6 + h, 1) = -kE[1][h];
      }
    }
    return true;
  }

 private:
  static constexpr double kSigmaC[2] = {1.5, 0.75};
  static constexpr double kAlpha[2][2] = {{0.5, 0.3}, {0.5, 0.7}};
  static constexpr double kE[2][2] = {{0, 60}, {25, 0}};
  static constexpr double kPhi[2] = {1.5, 2.0};
  static constexpr double kDelta[2][2] = {{0.6, 0.7}, {0.4, 0.3}};
  static constexpr double kSigma[2] = {2.0, 0.5};
};

// ---- Wall's chemical equilibrium (wallmcp) -------------------------------------------
// GAMS model library wallmcp.gms (SEQ=127), from T. W. Wall, D. Greening and R. E. D.
// Woolsey, "Solving complex chemical equilibria using a geometric-programming based
// technique", Oper. Res. 34 (1986). Free variables z = (ba, so4, baoh, oh, hso4, h)
// (concentrations scaled by 1e-5, 1e-5, 1e-12, 1e-7, 1e-10, 1e-7), equations
//   r1: ba so4 - 1 = 0          r2: baoh / (ba oh) - 4.8 = 0
//   r3: hso4 / (so4 h) - 0.98 = 0     r4: h oh - 1 = 0
//   b1: ba + 1e-7 baoh - so4 - 1e-5 hso4 = 0
//   b2: 2 ba + 1e-7 baoh + 1e-2 h - 2 so4 - 1e-5 hso4 - 1e-2 oh = 0.
// Evaluate() returns false where ba oh = 0 or so4 h = 0.
class WallFunction : public internal::DenseJacobianFunction {
 public:
  WallFunction() : DenseJacobianFunction(6) {}
  bool Evaluate(const Vector& z, Vector* F) override {
    const double ba = z(0), so4 = z(1), baoh = z(2), oh = z(3), hso4 = z(4), h = z(5);
    if (ba * oh == 0.0 || so4 * h == 0.0) return false;
    (*F)(0) = ba * so4 - 1;
    (*F)(1) = baoh / (ba * oh) - 4.8;
    (*F)(2) = hso4 / (so4 * h) - 0.98;
    (*F)(3) = h * oh - 1;
    (*F)(4) = ba + 1e-7 * baoh - so4 - 1e-5 * hso4;
    (*F)(5) = 2 * ba + 1e-7 * baoh + 1e-2 * h - 2 * so4 - 1e-5 * hso4 - 1e-2 * oh;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& z, DenseMatrix* J) override {
    const double ba = z(0), so4 = z(1), baoh = z(2), oh = z(3), hso4 = z(4), h = z(5);
    if (ba * oh == 0.0 || so4 * h == 0.0) return false;
    *J << so4, ba, 0, 0, 0, 0,                                                   //
        -baoh / (ba * ba * oh), 0, 1 / (ba * oh), -baoh / (ba * oh * oh), 0, 0,  //
        0, -hso4 / (so4 * so4 * h), 0, 0, 1 / (so4 * h), -hso4 / (so4 * h * h),  //
        0, 0, 0, h, 0, oh,                                                       //
        1, -1, 1e-7, 0, -1e-5, 0,                                                //
        2, -2, 1e-7, -1e-2, -1e-5, 1e-2;
    return true;
  }
};

}  // namespace

TestProblem ColvilleDual() {
  TestProblem p;
  p.name = "colvdual";
  p.source =
      "Colville (1968) test problem 2, dual form = Hock and Schittkowski (1981) problem "
      "117, as its KKT system (MCPLIB colvdual, Dirkse and Ferris 1995); data from "
      "GAMS-dev/gamsworld PrincetonLib/Hock and Schittkowski Suite/Indexed_models/"
      "hs117.gms, checked against JuliaSmoothOptimizers/OptimizationProblems.jl "
      "src/hs117.jl";
  p.F = std::make_unique<ColvilleDualFunction>();
  MakeStandardNcp(&p);
  Vector hs(20);
  hs << Hs117Start(), Vector::Zero(5);
  p.starts = {{"hs117", hs}, {"zero", Vector::Zero(20)}};
  // Computed (solver from colvnlp's solution mapped as (lambda, w, u = w), tolerance
  // 1e-14); the test checks it against HS117's published x* (7 digits, which are
  // themselves accurate to ~1e-4) and f* = 32.34867897, and recomputes its residual.
  p.solutions = {Vec({0,
                      0,
                      5.1740407276981717,
                      0,
                      3.0611086877584497,
                      11.839545664800729,
                      0,
                      0,
                      0.10389619077061552,
                      0,
                      0.30000000000000004,
                      0.33346760653460705,
                      0.40000000000000002,
                      0.42831010478169868,
                      0.22396487356079817,
                      0.29999999999999999,
                      0.33346760653460711,
                      0.40000000000000002,
                      0.42831010478169873,
                      0.22396487356079817})};
  p.notes =
      "z = (x_1..x_15 of HS117, multipliers u_1..u_5); the MCPLIB .gms file was not "
      "available: this is the KKT system of the published NLP (n = 20 as in MCPLIB); "
      "'hs117' is HS's start with u = 0, 'zero' is added here (not from a source). "
      "Observed with this solver (not documented in the literature): plain FB and "
      "penalized FB stall at stationary points of their merit functions (||Phi||_inf ~ "
      "0.14; the Lagrangian is nonconvex in (w, u)) from both starts; the default "
      "restarts "
      "(Options::merit_restarts: switch FB <-> penalized FB from the point projected "
      "onto "
      "the box) solve it. min hits max_iterations";
  return p;
}

TestProblem ColvilleNlp() {
  TestProblem p;
  p.name = "colvnlp";
  p.source =
      "Colville (1968) test problem 2, primal form (the NLP whose Wolfe dual is Hock and "
      "Schittkowski (1981) problem 117), as its KKT system (MCPLIB colvnlp, Dirkse and "
      "Ferris 1995); data as for colvdual (GAMS-dev/gamsworld hs117.gms)";
  p.F = std::make_unique<ColvilleNlpFunction>();
  MakeStandardNcp(&p);
  const Vector h = Hs117Start();
  Vector hs(15);
  hs << h.tail(5), h.head(10);  // w from HS117's w, lambda from HS117's v
  p.starts = {{"hs117", hs}, {"zero", Vector::Zero(15)}};
  // Computed (default solver from 'hs117', then tolerance 1e-14); equals colvdual's
  // (w, v) as duality requires, checked by the test with its residual.
  p.solutions = {
      Vec({0.29999999999999999, 0.33346760653460711, 0.39999999999999997,
           0.42831010478169873, 0.22396487356079806, 0, 0, 5.1740407276981699, 0,
           3.0611086877584492, 11.839545664800729, 0, 0, 0.1038961907706151, 0})};
  p.notes =
      "z = (w_1..w_5, lambda_1..lambda_10); primal min e'w + w'Cw + d'w^3, Aw >= b, "
      "w >= 0, optimum -32.34867897 (minus HS117's f*); the MCPLIB .gms file was not "
      "available: this is the KKT system of the NLP (n = 15 as in MCPLIB); 'hs117' maps "
      "HS117's start (w <- x_11..15, lambda <- x_1..10), 'zero' is added here";
  return p;
}

// ---- transmcp ------------------------------------------------------------------------
// GAMS model library transmcp.gms (SEQ=126), model fixedqty: Dantzig's transportation
// problem (G. B. Dantzig, "Linear Programming and Extensions", Princeton Univ. Press
// (1963), ch. 3.3) as an LCP. Plants i (seattle, san-diego), markets j (new-york,
// chicago, topeka); z = (x_ij (6, row-major), w_i (2), p_j (3)):
//   F_x_ij = w_i + c_ij - p_j         perp x_ij >= 0   (profit)
//   F_w_i  = a_i - sum_j x_ij         perp w_i >= 0    (supply)
//   F_p_j  = sum_i x_ij - b_j         perp p_j >= 0    (fxdemand)
// a = (350, 600) cases, b = (325, 300, 275) cases, c_ij = 90 $/case/1000 miles * d_ij /
// 1000 (thousands of $ per case), d = [2.5 1.7 1.8; 2.5 1.8 1.4] thousands of miles.
TestProblem TransMcp() {
  const double a[2] = {350, 600}, b[3] = {325, 300, 275};
  const double d[2][3] = {{2.5, 1.7, 1.8}, {2.5, 1.8, 1.4}};
  DenseMatrix M = DenseMatrix::Zero(11, 11);
  Vector q = Vector::Zero(11);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j) {
      const int x = 3 * i + j;
      M(x, 6 + i) = 1;
      M(x, 8 + j) = -1;
      q(x) = 90.0 * d[i][j] / 1000.0;
      M(6 + i, x) = -1;
      M(8 + j, x) = 1;
    }
  for (int i = 0; i < 2; ++i) q(6 + i) = a[i];
  for (int j = 0; j < 3; ++j) q(8 + j) = -b[j];
  TestProblem p;
  p.name = "transmcp";
  p.source =
      "GAMS model library transmcp.gms (SEQ=126), model fixedqty; Dantzig (1963), "
      "ch. 3.3";
  p.F = std::make_unique<AffineFunction>(SparseMatrix(M.sparseView()), q);
  MakeStandardNcp(&p);
  Vector gams = Vector::Zero(11);
  gams.tail(5).setOnes();  // p.l = 1, w.l = 1, x.l = 0 (GAMS default)
  p.starts = {{"gams", gams}, {"zero", Vector::Zero(11)}};
  // By hand: the transportation LP's optimum (cost 153.675) with its duals; w = 0 since
  // both plants ship to new-york, and san-diego's capacity is slack.
  p.solutions = {Vec({50, 300, 0, 275, 0, 275, 0, 0, 0.225, 0.153, 0.126})};
  p.notes =
      "monotone LCP (skew M); unique solution, degenerate in w_seattle (w = 0 and "
      "supply slack 0); 'zero' is added here";
  return p;
}

// ---- harkmcp -------------------------------------------------------------------------
// GAMS model library harkmcp.gms (SEQ=128), model harker with monopoly = 0, acp = 1 (its
// first solve: classical spatial price equilibrium, average-cost pricing of transport);
// P. T. Harker, "Alternative models of spatial competition", Oper. Res. 34 (1986)
// 410-425. Nodes n = 1..6, regions l = 1..3 (the first three nodes), 14 arcs (n, n')
// with transport cost kappa t + nu t^3 on the arc. z = (d (3), c (6), p (3), x (3),
// t (14), y (3)):
//   F_d_l = eta_l d_l - rho_l + p_l                                    perp d_l >= 0
//   F_c_n = [n in l](y_n - x_n) + sum_{arcs into n} t - sum_{arcs out of n} t
//                                                                      perp c_n >= 0
//   F_p_l = x_l - d_l                                                  perp p_l >= 0
//   F_x_l = c_l - p_l                                                  perp x_l >= 0
//   F_t_a = c_from(a) + kappa_a + nu_a t_a^2 - c_to(a)                 perp t_a >= 0
//   F_y_l = alpha_l + 2 beta_l y_l - c_l                               perp y_l >= 0
// (the GAMS factor (3 - 2 acp) on nu t^2 is 1 here).
class HarkerFunction : public internal::DenseJacobianFunction {
 public:
  HarkerFunction() : DenseJacobianFunction(32) {}
  bool Evaluate(const Vector& z, Vector* F) override {
    for (int l = 0; l < 3; ++l) {
      (*F)(D0 + l) = kEta[l] * z(D0 + l) - kRho[l] + z(P0 + l);
      (*F)(P0 + l) = z(X0 + l) - z(D0 + l);
      (*F)(X0 + l) = z(C0 + l) - z(P0 + l);
      (*F)(Y0 + l) = kAlpha[l] + 2 * kBeta[l] * z(Y0 + l) - z(C0 + l);
    }
    for (int n = 0; n < 6; ++n) (*F)(C0 + n) = n < 3 ? z(Y0 + n) - z(X0 + n) : 0.0;
    for (int a = 0; a < kArcs; ++a) {
      const int from = kArc[a].from - 1, to = kArc[a].to - 1;
      const double t = z(T0 + a);
      (*F)(C0 + to) += t;
      (*F)(C0 + from) -= t;
      (*F)(T0 + a) = z(C0 + from) + kArc[a].kappa + kArc[a].nu * t * t - z(C0 + to);
    }
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& z, DenseMatrix* J) override {
    for (int l = 0; l < 3; ++l) {
      (*J)(D0 + l, D0 + l) = kEta[l];
      (*J)(D0 + l, P0 + l) = 1;
      (*J)(P0 + l, X0 + l) = 1;
      (*J)(P0 + l, D0 + l) = -1;
      (*J)(X0 + l, C0 + l) = 1;
      (*J)(X0 + l, P0 + l) = -1;
      (*J)(Y0 + l, Y0 + l) = 2 * kBeta[l];
      (*J)(Y0 + l, C0 + l) = -1;
      (*J)(C0 + l, Y0 + l) = 1;
      (*J)(C0 + l, X0 + l) = -1;
    }
    for (int a = 0; a < kArcs; ++a) {
      const int from = kArc[a].from - 1, to = kArc[a].to - 1;
      (*J)(C0 + to, T0 + a) += 1;
      (*J)(C0 + from, T0 + a) -= 1;
      (*J)(T0 + a, C0 + from) = 1;
      (*J)(T0 + a, C0 + to) = -1;
      (*J)(T0 + a, T0 + a) = 2 * kArc[a].nu * z(T0 + a);
    }
    return true;
  }

 public:
  static constexpr int D0 = 0, C0 = 3, P0 = 9, X0 = 12, T0 = 15, Y0 = 29;

 private:
  struct Arc {
    int from, to;
    double kappa, nu;
  };
  static constexpr int kArcs = 14;
  static constexpr Arc kArc[kArcs] = {
      {1, 4, 1, 0.5},  {1, 5, 2, 0.2}, {2, 6, 3, 0.3}, {3, 6, 1, 0.4}, {4, 1, 2, 0.3},
      {4, 5, 1, 0.1},  {4, 6, 1, 0.1}, {5, 1, 3, 0.5}, {5, 4, 2, 0.2}, {5, 6, 1, 1.0},
      {6, 2, 2, 0.25}, {6, 3, 2, 0.2}, {6, 4, 1, 0.9}, {6, 5, 3, 0.8}};
  static constexpr double kAlpha[3] = {1, 2, 1.5};
  static constexpr double kBeta[3] = {0.5, 0.4, 0.3};
  static constexpr double kRho[3] = {19, 27, 30};
  static constexpr double kEta[3] = {0.2, 0.01, 0.3};
};

TestProblem HarkMcp() {
  using H = HarkerFunction;
  TestProblem p;
  p.name = "harkmcp";
  p.source =
      "GAMS model library harkmcp.gms (SEQ=128), model harker, monopoly = 0, acp = 1; "
      "Harker, Oper. Res. 34 (1986) 410-425";
  p.F = std::make_unique<HarkerFunction>();
  MakeStandardNcp(&p);
  Vector gams = Vector::Zero(32);  // t.l = 0, y.l = 25, x.l = c.l = d.l = p.l = 1
  gams.segment(H::D0, 3).setOnes();
  gams.segment(H::C0, 6).setOnes();
  gams.segment(H::P0, 3).setOnes();
  gams.segment(H::X0, 3).setOnes();
  gams.segment(H::Y0, 3).setConstant(25);
  p.starts = {{"gams", gams}, {"zero", Vector::Zero(32)}};
  // Computed (solver from 'gams', tolerance 1e-14); the test recomputes its residual.
  p.solutions = {Vec({12.099131626218632,
                      34.365510578493904,
                      31.62397505854171,
                      16.580173674756271,
                      26.65634489421506,
                      20.512807482437488,
                      20.025402111210507,
                      18.90255269538045,
                      21.514447798501354,
                      16.580173674756271,
                      26.65634489421506,
                      20.512807482437488,
                      12.099131626218632,
                      34.365510578493904,
                      31.62397505854171,
                      2.2114377388722626,
                      1.269604309665378,
                      0,
                      0.064037412187439913,
                      0,
                      0,
                      2.2114377388722626,
                      0,
                      0,
                      1.269604309665378,
                      3.5450794607250806,
                      0,
                      0,
                      0,
                      15.580173674756274,
                      30.820431117768823,
                      31.688012470729149})};
  p.notes =
      "the .gms starts from its own levels ('gams'); 'zero' is added here; no published "
      "solution values were found (solution computed, verified by the test)";
  return p;
}

TestProblem ScarfMcp() {
  // Commodities (capeop, nondurbl, durable, capbop, skillab, unsklab), consumers
  // agent1..agent5, sectors (d1, d2, n1, n2, n3, cd, c1, c2); data of scarfmcp.gms.
  DenseMatrix e = Rows(6, 5, {0,   0,   0,   0,   0,    // capeop
                              0,   0,   0,   0,   0,    // nondurbl
                              1,   2,   1.5, 1,   2,    // durable
                              3,   0.1, 2,   1,   6,    // capbop
                              5,   0.1, 6,   0.1, 0.1,  // skillab
                              0.1, 7,   0.1, 8,   0.5});
  DenseMatrix d = Rows(6, 5, {4,   0.4, 2,   5,   3,      // capeop
                              2,   4,   2,   5,   4,      // nondurbl
                              3.2, 1,   1.5, 4.5, 2,      // durable
                              0,   0,   0,   0,   0,      // capbop
                              0.2, 0,   0.5, 0,   0,      // skillab
                              0,   0.6, 0,   0.2, 0.2});  // unsklab
  // a = output - input:   d1    d2     n1    n2    n3   cd    c1    c2
  DenseMatrix a = Rows(6, 8, {4,    4,   1.6, 1.6, 1.6, 0.9, 7,  8,     // capeop
                              0,    0,   6,   8,   7,   0,   0,  0,     // nondurbl
                              4,    3.5, 0,   0,   0,   0,   0,  0,     // durable
                              -5.3, -5,  -2,  -2,  -2,  -1,  -4, -5,    // capbop
                              -2,   -1,  -2,  -4,  -1,  0,   -3, -2,    // skillab
                              -1,   -6,  -3,  -1,  -8,  0,   -1, -8});  // unsklab
  auto model =
      std::make_unique<ActivityAnalysisModel>(a, e, d, Vec({1.2, 1.6, 0.8, 0.5, 0.6}));
  const int nc = 6, ns = 8, nh = 5;
  Vector lower(nc + ns + nh);
  lower.setZero();
  for (int c = 0; c < nc; ++c) lower(c) = model->Demanded(c) ? 1e-5 : 0.0;
  // GAMS start: p.l = 1, y.l = 1, i.l = sum_c p.l e(c,h); i(agent1) fixed at its level.
  Vector gams(nc + ns + nh);
  gams.head(nc + ns).setOnes();
  gams.tail(nh) = e.colwise().sum().transpose();
  const double fixed_income = gams(nc + ns);
  TestProblem p;
  p.name = "scarfmcp";
  p.source =
      "GAMS model library scarfmcp.gms (SEQ=132) (copy read: MonicaCT/SalariesBolivia "
      "scarfmcp.gms); Scarf and Hansen, The Computation of Economic Equilibria (1973)";
  p.F = std::make_unique<ReducedFunction>(
      std::move(model), std::vector<std::pair<int, double>>{{nc + ns, fixed_income}});
  const int n = nc + ns + nh - 1;
  p.lower = lower.head(n);
  p.upper = Vector::Constant(n, kInf);
  Vector start(n);
  start << gams.head(nc + ns), gams.tail(nh - 1);
  p.starts = {{"gams", start}};
  // Computed (solver from 'gams', tolerance 1e-14; entries below 1e-20 set to 0); no
  // published solution values were found. The test recomputes its residual.
  p.solutions = {Vec({1.1324994814649578, 0.54526016270026501, 1.0618849588356167,
                      1.290535010515798, 0.82765412272294447, 0.28239396002267941,
                      0.46349293456246449, 0, 3.9391950568227068, 0.0060229906067056308,
                      0, 0, 0.43826283799002824, 0, 4.3123465511538637, 9.168061591624955,
                      4.694337061805145, 10.090942373049655})};
  p.notes =
      "z = (p (6), y (8), i_agent2..5); i_agent1 = 9.1 fixed (numeraire) as in the "
      ".gms; same economy as MCPLIB scarfanum/scarfasum, whose own numeraire/"
      "normalization files were not available; solution computed and verified by the "
      "test";
  return p;
}

TestProblem HansMcp() {
  // Commodities (agric, food, textiles, hserv, entert, houseop, capeop, steel, coal,
  // lumber, housbop, capbop, labor, exchange), consumers agent1..4, sectors dom1..dom12,
  // imp1..imp7, exp1..exp7; data of hansmcp.gms, a = output - input.
  DenseMatrix a = Rows(14, 26,
                       {
#include "mcplib_hansmcp_a.inc"
                       });
  DenseMatrix e = DenseMatrix::Zero(14, 4);
  e.row(10) << 2, 0.4, 0, 0.8;    // housbop
  e.row(11) << 3, 2, 0, 7.5;      // capbop
  e.row(12) << 0.6, 0.8, 1, 0.6;  // labor
  DenseMatrix d = DenseMatrix::Zero(14, 4);
  d.row(0) << 0.1, 0.2, 0.3, 0.1;  // agric
  d.row(1) << 0.2, 0.2, 0.2, 0.2;  // food
  d.row(2) << 0.1, 0.1, 0.3, 0.1;  // textiles
  d.row(3) << 0.1, 0.1, 0.1, 0.1;  // hserv
  d.row(4) << 0.1, 0.1, 0.1, 0.1;  // entert
  d.row(5) << 0.3, 0.1, 0, 0.1;    // houseop
  d.row(6) << 0.1, 0.2, 0, 0.3;    // capeop
  auto model = std::make_unique<ActivityAnalysisModel>(a, e, d, Vector::Ones(4));
  const int nc = 14, ns = 26, nh = 4;
  Vector lower = Vector::Zero(nc + ns + nh);
  for (int c = 0; c < nc; ++c) lower(c) = model->Demanded(c) ? 1e-5 : 0.0;
  TestProblem p;
  p.name = "hansmcp";
  p.source =
      "GAMS model library hansmcp.gms (SEQ=135); Scarf and Hansen, The Computation of "
      "Economic Equilibria (1973)";
  p.F = std::make_unique<ReducedFunction>(std::move(model),
                                          std::vector<std::pair<int, double>>{{0, 1.0}});
  const int n = nc + ns + nh - 1;
  p.lower = lower.tail(n);
  p.upper = Vector::Constant(n, kInf);
  p.starts = {{"gams", Vector::Ones(n)}};  // p.l = y.l = i.l = 1
  // Computed (solver from 'gams', tolerance 1e-14; entries below 1e-20 set to 0); no
  // published solution values were found. The test recomputes its residual.
  p.solutions = {Vec({0.93868577430260969,
                      1.5359047996213004,
                      1.1496499916556695,
                      1.0596641943528444,
                      1.0049090244221799,
                      1.1087235779882341,
                      1.5787620359458738,
                      1.4520544311389909,
                      1.2801525232865285,
                      0.90441812197996185,
                      0.99785122018941053,
                      0.58758143169220001,
                      1.4930475632967268,
                      0.47923372408848713,
                      0,
                      0,
                      5.1971402868660732,
                      0.40413799553361607,
                      0,
                      0,
                      0,
                      3.0500349778218663,
                      2.1184797234458581,
                      3.6894498517263195,
                      2.8028597131339259,
                      0,
                      4.4044092091081373,
                      2.3646437525683748,
                      0,
                      2.5642742071044098,
                      0,
                      1.2052967135691404,
                      0,
                      0,
                      0,
                      4.7284682461568801,
                      0,
                      0,
                      0,
                      5.1549387635434751,
                      2.8275348345245663,
                      0.58758143169220001,
                      8.5599675080198683})};
  p.notes =
      "z = (p_food..p_exchange (13), y (26), i (4)); p_agric = 1 fixed (numeraire) as in "
      "the .gms; Cobb-Douglas demand (esub = 1); same economy as MCPLIB scarfbnum/"
      "scarfbsum, whose own files were not available; solution computed and verified by "
      "the test";
  return p;
}

TestProblem Two3Mcp() {
  TestProblem p;
  p.name = "two3mcp";
  p.source =
      "GAMS model library two3mcp.gms (SEQ=131), model jel, reference case; Shoven and "
      "Whalley, J. Econ. Literature 22 (1984)";
  p.F = std::make_unique<ReducedFunction>(std::make_unique<Two3Model>(),
                                          std::vector<std::pair<int, double>>{{0, 1.0}});
  // z = (W_capital, P (2), Y (2), I (2))
  p.lower = Vec({1e-4, 1e-4, 1e-4, 0, 0, 0, 0});
  p.upper = Vector::Constant(7, kInf);
  // W.l = 1, P.l = 1, Y.l = 10, I.l = sum_f W.l e(f,h) = (25, 60)
  p.starts = {{"gams", Vec({1, 1, 1, 10, 10, 25, 60})}};
  // Computed (solver from 'gams', tolerance 1e-14; entries below 1e-20 set to 0); no
  // published solution values were found. The test recomputes its residual.
  p.solutions = {Vec({1.3734711469786707, 1.3991106622318159, 1.0930764800086183,
                      24.942472866207879, 54.378170267151781, 34.336778674466764, 60})};
  p.notes = "W_labor = 1 fixed (numeraire); solution computed and verified by the test";
  return p;
}

TestProblem WallMcp() {
  TestProblem p;
  p.name = "wallmcp";
  p.source =
      "GAMS model library wallmcp.gms (SEQ=127); Wall, Greening and Woolsey, Oper. Res. "
      "34 (1986)";
  p.F = std::make_unique<WallFunction>();
  p.lower = Vector::Constant(6, -kInf);
  p.upper = Vector::Constant(6, kInf);
  p.starts = {{"gams", Vector::Ones(6)}};  // all .l = 1
  // Computed (solver from 'gams', tolerance 1e-14; entries below 1e-20 set to 0); no
  // published solution values were found. The test recomputes its residual.
  p.solutions = {Vec({1.0000046575934247, 0.99999534242826837, 4.8022585271348994,
                      1.0004658667231947, 0.9795391009085217, 0.99953435020754833})};
  p.notes =
      "square nonlinear system, all variables free; solution computed and verified by "
      "the test";
  return p;
}

std::vector<TestProblem> McplibNlpProblems() {
  std::vector<TestProblem> problems;
  problems.push_back(ColvilleDual());
  problems.push_back(ColvilleNlp());
  problems.push_back(TransMcp());
  problems.push_back(HarkMcp());
  problems.push_back(ScarfMcp());
  problems.push_back(HansMcp());
  problems.push_back(Two3Mcp());
  problems.push_back(WallMcp());
  return problems;
}

}  // namespace ncp::collection
