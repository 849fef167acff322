// Dormand-Prince 5(4) with Hairer's dopri5 step-size control, on the first-order system y = (x, v), y' = (v, a).
// Each step(t, h) covers [t, t + h] with as many adaptive substeps as the tolerance needs, the last one clipped to
// land exactly on t + h; the controller's preferred substep carries over to the next call.
// Order 5 (the 4th-order embedded solution only estimates the error), 7 stages, first-same-as-last: 6 new
// evaluations per attempted substep, plus one on a call whose start state is not the previous call's end state
// (Simulation corrects contacts between calls). Explicit: the substep shrinks to what stiffness allows, so it is
// stable on stiff systems but slow on them.
// Options: rtol, atol (error per substep, norm below; the global error usually lands within 1-100x of them);
// max_substeps (attempted substeps per call before std::runtime_error). A substep shorter than ~10 ulps of t also
// throws std::runtime_error: the problem is too stiff or non-smooth for the tolerance.
//   err = sqrt(1/n sum((e_i / sk_i)^2)), sk_i = atol + rtol max(|y0_i|, |y1_i|), accept when err <= 1;
//   fac = clamp(err^(0.2 - 0.75 beta) / facold^beta / 0.9, 1/10, 1/0.2), h_new = h / fac, beta = 0.04,
//   facold = max(err, 1e-4) after each accepted substep; no growth on the substep right after a rejection.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

// Butcher tableau (Dormand & Prince 1980, as in Hairer's dopri5).
constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
constexpr double a21 = 1.0 / 5;
constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176, a65 = -5103.0 / 18656;
constexpr double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192, a75 = -2187.0 / 6784, a76 = 11.0 / 84;
// Difference between the 5th- and 4th-order weights.
constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                 e7 = -1.0 / 40;

constexpr double kBeta = 0.04, kSafety = 0.9, kFacMin = 0.2, kFacMax = 10;
constexpr double kExpo1 = 0.2 - kBeta * 0.75;

class DormandPrince45 final : public Integrator {
 public:
  explicit DormandPrince45(const IntegratorOptions& o) : rtol_(o.rtol), atol_(o.atol), max_substeps_(o.max_substeps) {
    if (!(rtol_ >= 0) || !(atol_ >= 0) || rtol_ + atol_ <= 0)
      throw std::invalid_argument("rk45: rtol and atol must be >= 0 and not both 0");
    if (max_substeps_ < 1) throw std::invalid_argument("rk45: max_substeps must be >= 1");
  }

  std::string_view name() const override { return "rk45"; }

  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    if (!(h > 0) || !std::isfinite(h)) throw std::invalid_argument("rk45: the step must be positive and finite");
    ++stats_.steps;
    const double t_end = t + h;
    // First same as last: the previous call's final derivative is this call's first, if nothing moved in between.
    const bool same_state = fsal_valid_ && &dynamics == fsal_dynamics_ && t == fsal_t_ && x.size() == fsal_x_.size() &&
                            v.size() == fsal_v_.size() && x == fsal_x_ && v == fsal_v_;
    if (!same_state) {
      evaluate(dynamics, t, x, v, kv_[0]);
    } else {
      kv_[0].swap(kv_[6]);
    }
    fsal_valid_ = false;  // until this call completes
    if (h_ <= 0) h_ = initialStep(dynamics, t, x, v, h);

    double tc = t;
    for (long attempt = 0;; ++attempt) {
      if (attempt >= max_substeps_) {
        std::ostringstream m;
        m << "rk45: more than " << max_substeps_ << " substeps to advance from t = " << t << " to " << t_end
          << " (stuck at t = " << tc << ", substep " << h_ << "); loosen rtol/atol or raise max_substeps";
        throw std::runtime_error(m.str());
      }
      // Clip onto t_end, and take a slightly short remainder in one go rather than leave a sliver (as dopri5 does).
      const bool last = tc + 1.01 * h_ >= t_end;
      const double hs = last ? t_end - tc : h_;
      const double h_min = 10 * std::numeric_limits<double>::epsilon() * std::max({std::abs(tc), std::abs(t_end), h});
      if (!(hs > h_min) && !(last && hs > 0 && attempt == 0)) {
        std::ostringstream m;
        m << "rk45: step size underflow at t = " << tc << " (substep " << hs
          << "): the problem is too stiff or not smooth enough for rtol = " << rtol_ << ", atol = " << atol_;
        throw std::runtime_error(m.str());
      }
      const double err = attemptSubstep(dynamics, tc, hs, x, v);
      const double fac11 = std::pow(err, kExpo1);
      if (err <= 1) {
        ++stats_.accepted;
        double fac = std::clamp(fac11 / std::pow(facold_, kBeta) / kSafety, 1 / kFacMax, 1 / kFacMin);
        double h_new = hs / fac;
        if (rejected_last_) h_new = std::min(h_new, hs);
        facold_ = std::max(err, 1e-4);
        rejected_last_ = false;
        x.swap(x1_);
        v.swap(kx_[6]);  // v1
        kv_[0].swap(kv_[6]);
        if (last) {
          // A substep clipped to land on t_end says little about the step the solution allows: keep the larger.
          h_ = hs < h_ ? std::max(h_new, h_) : h_new;
          break;
        }
        tc += hs;
        h_ = h_new;
      } else {
        ++stats_.rejected;
        // NaN or inf error (a blown-up stage) shrinks the most.
        const double fac = std::isfinite(err) ? std::min(1 / kFacMin, fac11 / kSafety) : 1 / kFacMin;
        h_ = hs / fac;
        rejected_last_ = true;
      }
    }
    stats_.next_substep = h_;
    // kv_[0] holds a(t_end, x, v) again; keep it for the next call.
    kv_[6].swap(kv_[0]);
    fsal_valid_ = true;
    fsal_dynamics_ = &dynamics;
    fsal_t_ = t_end;
    fsal_x_ = x;
    fsal_v_ = v;
  }

 private:
  void evaluate(const Dynamics& dynamics, double t, const VecX& x, const VecX& v, VecX& a) {
    ++stats_.evaluations;
    dynamics.acceleration(t, x, v, a);
  }

  // Stages from (x, v) with kv_[0] = a(t, x, v); leaves y1 in (x1_, kx_[6]), a(y1) in kv_[6]; returns the error norm.
  double attemptSubstep(const Dynamics& dyn, double t, double h, const VecX& x, const VecX& v) {
    auto& V = kx_;  // stage velocities: the x-part of each stage derivative
    auto& A = kv_;  // stage accelerations: the v-part
    // The stage updates run elementwise over segments (forEachSegment): the same bytes on any number of threads.
    const Eigen::Index size = x.size();
    xs_.resize(size);
    x1_.resize(size);
    for (VecX& k : V) k.resize(size);
    const auto update = [&](auto&& fn) {
      forEachSegment(size, [&](Eigen::Index i, Eigen::Index n) { fn([&](auto& y) { return y.segment(i, n); }); });
    };
    // xs_ (x1_ last) = x + h sum a_j V[j], V[s] = v + h sum a_j A[j], on segments s(y) of the vectors.
    update([&](auto s) {
      s(V[0]) = s(v);
      s(xs_) = s(x) + h * (a21 * s(V[0]));
      s(V[1]) = s(v) + h * (a21 * s(A[0]));
    });
    evaluate(dyn, t + c2 * h, xs_, V[1], A[1]);
    update([&](auto s) {
      s(xs_) = s(x) + h * (a31 * s(V[0]) + a32 * s(V[1]));
      s(V[2]) = s(v) + h * (a31 * s(A[0]) + a32 * s(A[1]));
    });
    evaluate(dyn, t + c3 * h, xs_, V[2], A[2]);
    update([&](auto s) {
      s(xs_) = s(x) + h * (a41 * s(V[0]) + a42 * s(V[1]) + a43 * s(V[2]));
      s(V[3]) = s(v) + h * (a41 * s(A[0]) + a42 * s(A[1]) + a43 * s(A[2]));
    });
    evaluate(dyn, t + c4 * h, xs_, V[3], A[3]);
    update([&](auto s) {
      s(xs_) = s(x) + h * (a51 * s(V[0]) + a52 * s(V[1]) + a53 * s(V[2]) + a54 * s(V[3]));
      s(V[4]) = s(v) + h * (a51 * s(A[0]) + a52 * s(A[1]) + a53 * s(A[2]) + a54 * s(A[3]));
    });
    evaluate(dyn, t + c5 * h, xs_, V[4], A[4]);
    update([&](auto s) {
      s(xs_) = s(x) + h * (a61 * s(V[0]) + a62 * s(V[1]) + a63 * s(V[2]) + a64 * s(V[3]) + a65 * s(V[4]));
      s(V[5]) = s(v) + h * (a61 * s(A[0]) + a62 * s(A[1]) + a63 * s(A[2]) + a64 * s(A[3]) + a65 * s(A[4]));
    });
    evaluate(dyn, t + h, xs_, V[5], A[5]);
    update([&](auto s) {
      s(x1_) = s(x) + h * (a71 * s(V[0]) + a73 * s(V[2]) + a74 * s(V[3]) + a75 * s(V[4]) + a76 * s(V[5]));
      s(V[6]) = s(v) + h * (a71 * s(A[0]) + a73 * s(A[2]) + a74 * s(A[3]) + a75 * s(A[4]) + a76 * s(A[5]));
    });
    evaluate(dyn, t + h, x1_, V[6], A[6]);
    // Local error estimate h sum e_i k_i, scaled per component.
    const auto scaled_square_sum = [&](const auto& err, const VecX& y0, const VecX& y1) {
      return (err.array() / (atol_ + rtol_ * y0.array().abs().max(y1.array().abs()))).square().sum();
    };
    const double sx =
        scaled_square_sum(h * (e1 * V[0] + e3 * V[2] + e4 * V[3] + e5 * V[4] + e6 * V[5] + e7 * V[6]), x, x1_);
    const double sv =
        scaled_square_sum(h * (e1 * A[0] + e3 * A[2] + e4 * A[3] + e5 * A[4] + e6 * A[5] + e7 * A[6]), v, V[6]);
    const double n = static_cast<double>(x.size() + v.size());
    return n > 0 ? std::sqrt((sx + sv) / n) : 0.0;
  }

  // Hairer, Norsett & Wanner, Solving ODEs I, II.4: a first guess from the sizes of y, y' and y''; at most h.
  double initialStep(const Dynamics& dyn, double t, const VecX& x, const VecX& v, double h_max) {
    const double n = static_cast<double>(x.size() + v.size());
    if (n == 0) return h_max;
    const auto rms = [&](const auto& fx, const auto& fv) {
      const double s = (fx.array() / (atol_ + rtol_ * x.array().abs())).square().sum() +
                       (fv.array() / (atol_ + rtol_ * v.array().abs())).square().sum();
      return std::sqrt(s / n);
    };
    const double d0 = rms(x, v), d1 = rms(v, kv_[0]);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = std::min(h0, h_max);
    xs_ = x + h0 * v;
    kx_[1] = v + h0 * kv_[0];
    evaluate(dyn, t + h0, xs_, kx_[1], kv_[1]);
    const double d2 = rms(kx_[1] - v, kv_[1] - kv_[0]) / h0;
    const double d12 = std::max(d1, d2);
    const double h1 = d12 <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / d12, 1.0 / 5);
    return std::min({100 * h0, h1, h_max});
  }

  double rtol_, atol_;
  long max_substeps_;
  double h_ = 0;  // preferred next substep; 0 until the first call picks one
  double facold_ = 1e-4;
  bool rejected_last_ = false;
  std::array<VecX, 7> kx_, kv_;  // stage derivatives (velocity part, acceleration part)
  VecX xs_, x1_;
  bool fsal_valid_ = false;
  const Dynamics* fsal_dynamics_ = nullptr;
  double fsal_t_ = 0;
  VecX fsal_x_, fsal_v_;
};

}  // namespace
std::unique_ptr<Integrator> makeRk45(const IntegratorOptions& options) {
  return std::make_unique<DormandPrince45>(options);
}
}  // namespace wobble
