// Backward (implicit) Euler for mass-spring systems, after Baraff & Witkin 1998, "Large Steps in Cloth Simulation".
// The step solves M dv = h F(x0 + h (v0 + dv), v0 + dv), x1 = x0 + h (v0 + dv). By default with one Newton step
// linearized at the start state:
//   (M - h dF/dv - h^2 dF/dx) dv = h (F0 + h dF/dx v0),
// assembled from triplets and solved by conjugate gradients with a Jacobi (diagonal) preconditioner, warm-started
// from the previous step's dv. First order; A-stable and L-stable (unconditionally stable on linear springs, strongly
// damps the fast modes: amplitude factor 1/sqrt(1 + (omega h)^2) per step on an undamped oscillator).
// Contact forces are explicit: they enter through F0 = M a(t, x0, v0) and are held fixed over the step; the
// Jacobians (ForceJacobian, from the Dynamics) cover springs, dampers and drag. Constraints use B&W's filter
// S = blockdiag(S_i), solving S A S y + (I - S) y = S (b - A z), dv = y + z: a pinned particle (inverse mass 0) has
// S_i = 0, dv_i = 0; a particle whose contact support is active at the start (ForceJacobian::contactConstraints) has
// S_i = I - n n^T and its normal dv prescribed (the surface's normal acceleration times h), which is what the explicit
// support force does instantaneously; friction stays explicit. Without that, the support sized to cancel a stiff
// spring's push at the start would act for the whole step while the spring relaxes and launch the body.
// Options: cg_tolerance (relative residual) and cg_max_iterations of each linear solve (a solve that hits the limit
// is used as it stands, as Blender's cloth solver does); newton: after that first step, iterate Newton on the full
// nonlinear equations (contact still held at its start value) with a backtracking line search on the residual,
// until max |M^-1 residual| <= newton_tolerance * max(1, max |v1|), at most newton_max_iterations linear solves
// (the damper's x-dependence is not in the Jacobian, so convergence is linear rather than quadratic when dampers
// act; it still converges to the exact backward-Euler step).
// Throws std::invalid_argument if the Dynamics offers no ForceJacobian.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "methods.h"

namespace wobble {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

class BackwardEuler final : public Integrator {
 public:
  explicit BackwardEuler(const IntegratorOptions& o) : options_(o) {
    if (!(o.cg_tolerance > 0) || o.cg_max_iterations < 1)
      throw std::invalid_argument("backward-euler: cg_tolerance must be > 0 and cg_max_iterations >= 1");
    if (o.newton && (!(o.newton_tolerance > 0) || o.newton_max_iterations < 1))
      throw std::invalid_argument("backward-euler: newton_tolerance must be > 0 and newton_max_iterations >= 1");
    cg_.setTolerance(o.cg_tolerance);
    cg_.setMaxIterations(o.cg_max_iterations);
  }

  std::string_view name() const override { return "backward-euler"; }

  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    const ForceJacobian* jacobian = dynamics.forceJacobian();
    if (!jacobian)
      throw std::invalid_argument(
          "backward-euler needs force Jacobians, and this Dynamics offers none (Dynamics::forceJacobian() is null)");
    ++stats_.steps;
    stats_.last_cg_iterations = 0;
    stats_.last_linear_solves = 0;
    stats_.last_residual = 0;
    setUpFilter(*jacobian, x.size());
    jacobian->contactConstraints(t, x, v, contacts_);
    z_.setZero(x.size());
    for (const ContactConstraint& c : contacts_) particle(z_, c.particle) = h * c.normal_acceleration * c.normal;

    // F0 = M a0: every force, contact included, at the start state.
    ++stats_.evaluations;
    dynamics.acceleration(t, x, v, f0_);
    f0_.array() *= mass_.array();

    // Linearized step at (x0, v0): rhs = h (F0 + h dF/dx v0), filtered: S (rhs - A z).
    assemble(*jacobian, t, x, v, h);
    rhs_ = f0_ + h * kv_;
    rhs_ *= h;
    if (!contacts_.empty()) rhs_ -= az_;
    filter(rhs_);
    if (dv_.size() != x.size()) dv_.setZero(x.size());  // else warm start from the last step's dv
    filter(dv_);
    solve(rhs_, dv_);
    dv_ += z_;

    if (options_.newton) newton(*jacobian, t, h, x, v);

    x += h * (v + dv_);
    v += dv_;
  }

 private:
  // Mass and filter (1 on free coordinates, 0 on pinned ones), per coordinate.
  void setUpFilter(const ForceJacobian& jacobian, Eigen::Index n) {
    const VecX& m = jacobian.mass();
    const VecX& inv_m = jacobian.inverseMass();
    if (3 * m.size() != n) throw std::invalid_argument("backward-euler: state size does not match the system's mass");
    mass_.resize(n);
    free_.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      mass_[i] = m[i / 3];
      free_[i] = inv_m[i / 3] != 0 ? 1.0 : 0.0;
    }
  }

  void filter(VecX& y) const {
    y.array() *= free_.array();
    for (const ContactConstraint& c : contacts_) {
      auto p = particle(y, c.particle);
      p -= c.normal.dot(p) * c.normal;
    }
  }

  // A = S (M - h dF/dv - h^2 dF/dx) S + (I - S), kv_ = dF/dx v with the Jacobians at (x, v), and az_ = A z before
  // the contact part of the filter (pinned rows and columns are left out while assembling; contacts need 3x3 blocks).
  void assemble(const ForceJacobian& jacobian, double t, const VecX& x, const VecX& v, double h) {
    ++stats_.jacobians;
    dfdx_.clear();
    dfdv_.clear();
    jacobian.addForceJacobians(t, x, v, dfdx_, dfdv_);
    const Eigen::Index n = x.size();
    kv_.setZero(n);
    a_.clear();
    a_.reserve(dfdx_.size() + dfdv_.size() + n);
    for (const auto& e : dfdx_) {
      kv_[e.row()] += e.value() * v[e.col()];
      if (free_[e.row()] != 0 && free_[e.col()] != 0) a_.emplace_back(e.row(), e.col(), -h * h * e.value());
    }
    for (const auto& e : dfdv_)
      if (free_[e.row()] != 0 && free_[e.col()] != 0) a_.emplace_back(e.row(), e.col(), -h * e.value());
    for (Eigen::Index i = 0; i < n; ++i) a_.emplace_back(i, i, free_[i] != 0 ? mass_[i] : 1.0);
    matrix_.resize(n, n);
    matrix_.setFromTriplets(a_.begin(), a_.end());
    if (!contacts_.empty()) {
      az_ = matrix_ * z_;
      // P = blockdiag(I, or I - n n^T at a contact), D = blockdiag(0, or n n^T): A <- P A P + D.
      p_.clear();
      d_.clear();
      std::size_t next = 0;  // contacts_ is in particle order
      for (Eigen::Index i = 0; i < n / 3; ++i) {
        Eigen::Matrix3d block = Eigen::Matrix3d::Identity();
        if (next < contacts_.size() && contacts_[next].particle == i) {
          const Vec3& nrm = contacts_[next++].normal;
          block -= nrm * nrm.transpose();
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) d_.emplace_back(3 * i + r, 3 * i + c, nrm[r] * nrm[c]);
        }
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            if (block(r, c) != 0) p_.emplace_back(3 * i + r, 3 * i + c, block(r, c));
      }
      projection_.resize(n, n);
      projection_.setFromTriplets(p_.begin(), p_.end());
      complement_.resize(n, n);
      complement_.setFromTriplets(d_.begin(), d_.end());
      matrix_ = projection_ * matrix_ * projection_ + complement_;
    }
    cg_.compute(matrix_);
  }

  // Solves A y = b, starting from y.
  void solve(const VecX& b, VecX& y) {
    y = cg_.solveWithGuess(b, y);
    ++stats_.last_linear_solves;
    stats_.last_cg_iterations += static_cast<int>(cg_.iterations());
    stats_.cg_iterations += cg_.iterations();
  }

  // r = S (M dv - h (Fs(x0 + h (v0 + dv), v0 + dv) + Fc)); returns max |M^-1 r|. Leaves the trial state in x1_, v1_.
  double residual(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, const VecX& dv,
                  VecX& r) {
    v1_ = v + dv;
    x1_ = x + h * v1_;
    ++stats_.evaluations;
    jacobian.smoothForce(t + h, x1_, v1_, fs_);
    r = mass_.cwiseProduct(dv) - h * (fs_ + fc_);
    filter(r);
    return (r.array() / mass_.array()).abs().maxCoeff();
  }

  // Newton on the nonlinear backward-Euler equations from the linearized step in dv_, with backtracking.
  void newton(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v) {
    // The contact forces in F0, held fixed: Fc = F0 - Fs(x0, v0).
    ++stats_.evaluations;
    jacobian.smoothForce(t, x, v, fs_);
    fc_ = f0_ - fs_;
    filter(fc_);
    double norm = residual(jacobian, t, h, x, v, dv_, r_);
    while (norm > options_.newton_tolerance * std::max(1.0, v1_.lpNorm<Eigen::Infinity>()) &&
           stats_.last_linear_solves < options_.newton_max_iterations) {
      assemble(jacobian, t + h, x1_, v1_, h);
      delta_.setZero(x.size());
      rhs_ = -r_;
      solve(rhs_, delta_);
      // Backtrack on the residual norm: halve the Newton step until it decreases (at most 10 halvings).
      double alpha = 1;
      for (int k = 0; k < 10; ++k, alpha /= 2) {
        trial_ = dv_ + alpha * delta_;
        const double trial_norm = residual(jacobian, t, h, x, v, trial_, trial_r_);
        if (trial_norm < norm || k == 9) {
          dv_.swap(trial_);
          r_.swap(trial_r_);
          norm = trial_norm;
          break;
        }
      }
    }
    stats_.last_residual = norm;
  }

  IntegratorOptions options_;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>> cg_;
  SparseMatrix matrix_, projection_, complement_;
  Triplets dfdx_, dfdv_, a_, p_, d_;
  std::vector<ContactConstraint> contacts_;
  VecX mass_, free_, f0_, kv_, rhs_, dv_, z_, az_;
  VecX fs_, fc_, r_, x1_, v1_, delta_, trial_, trial_r_;  // Newton only
};

}  // namespace
std::unique_ptr<Integrator> makeBackwardEuler(const IntegratorOptions& options) {
  return std::make_unique<BackwardEuler>(options);
}
}  // namespace wobble
