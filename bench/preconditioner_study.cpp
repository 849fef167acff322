// CG iterations of backward Euler's systems under block-Jacobi and several two-level preconditioners built on the
// solver's own aggregates (coarse_correction.h), each with an exact coarse solve: a yardstick for the next
// preconditioner, not the solver. Matrices are plain Eigen sparse ones (slow, clear); the system is
// A^ = S A S + (I - S) with A = M - h df/dv - h^2 df/dx (contact stencils included), S the filter, B block-Jacobi,
// W = S Z a coarse space and Q = W (W^T A^ W)^-1 W^T. The coarse spaces:
// - translations: Z_p = I3 in its aggregate's three columns (the solver's);
// - rotations too: Z_p = [I3, -[x_p - c_I]_x / r_I] in six columns per aggregate I, c_I its centre, r_I its RMS
//   radius: the rigid-body modes of smoothed aggregation for elasticity (Vanek, Mandel & Brezina 1996). Each
//   aggregate's columns are orthonormalised (W_I V_I L_I^-1/2 over the eigenpairs of W_I^T W_I above 1e-9 of the
//   largest), which drops the directions S removes or a flat aggregate lacks;
// - smoothed: P = (I - omega B A^) W, one damped block-Jacobi step on either space (omega = 4 / (3 rho(B A^)), rho by
//   power iteration), Q = P (P^T A^ P)^-1 P^T: smoothed aggregation's prolongation.
// Two modes.
//   build/preconditioner_study [SIDE]: the stiff cloth (stiff_cloth_bench's cloth, or SIDE x SIDE; ks 1e5, dt 1/60,
//   corners pinned) at four moments of its fall, the right-hand side a gravity impulse with 1% noise, CG from 0 to a
//   relative residual of 1e-3 (the solver's default); also the additive combinations besides B + Q.
//   build/preconditioner_study stacked|folded SIDE CONTACT [STEPS], or jelly SIDE [STEPS]: the systems the solver
//   itself solves (captured through setPcgSystemTap) in STEPS steps (default 10) after body_contact_bench's warm-up
//   (0.5 s: steps 31 to 40 of BM_Stacked / BM_Folded), each solved from the solver's own start x0 to its tolerance
//   (relative to |S (b - A (I - S) x0)|), summed a step; the jelly: a SIDE^3 jelly, ks 1e5, landed on a floor.
//   The solver's own iterations are printed beside (float iterations, kept factorizations, the error rule).
#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/force_jacobian.h"
#include "sim/integrators/integrator.h"
#include "sim/simulation.h"
#include "sim/solver/coarse_correction.h"
#include "sim/solver/filtered_pcg.h"
#include "tests/sim/folded_cloth.h"

namespace wobble {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;
using Preconditioner = std::function<VecX(const VecX&)>;

void addBlock(Triplets& t, int i, int j, const Eigen::Matrix3d& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (m(r, c) != 0) t.emplace_back(3 * i + r, 3 * j + c, m(r, c));
}

// A system as the solver sees it, in Eigen's matrices.
struct System {
  int n = 0;
  SparseMatrix a;       // S A S + (I - S)
  SparseMatrix jacobi;  // B: per particle S_p (A^_pp)^-1 S_p
  std::vector<int> aggregate;
  int aggregates = 0;
  std::vector<Eigen::Matrix3d> s;  // S_p
  std::vector<Vec3> x;             // positions (the rotations' lever arms)
};

System capture(const PairBlockMatrix& m, const ParticleFilter& filter, const VecX& positions) {
  System sys;
  const PairSchedule& pattern = *m.pattern();
  const int n = sys.n = pattern.particles();
  sys.s.resize(n);
  sys.x.resize(n);
  for (int p = 0; p < n; ++p) sys.s[p] = filter.matrix(p), sys.x[p] = particle(positions, p);
  Triplets t;
  const auto add = [&](int i, int j, const Eigen::Matrix3d& b) { addBlock(t, i, j, sys.s[i] * b * sys.s[j]); };
  for (int p = 0; p < n; ++p) {
    add(p, p, m.self()[p] * Eigen::Matrix3d::Identity());
    addBlock(t, p, p, Eigen::Matrix3d::Identity() - sys.s[p]);
  }
  for (std::size_t e = 0; e < pattern.size(); ++e) {
    const int i = pattern.a()[e], j = pattern.b()[e];
    const Eigen::Matrix3d w = m.pair(e).dense();
    add(i, i, w), add(j, j, w), add(i, j, -w), add(j, i, -w);
  }
  for (const StencilBlock& sb : m.stencils()) {
    const Eigen::Matrix3d b = sb.block.dense();
    for (int i = 0; i < sb.stencil.size; ++i)
      for (int j = 0; j < sb.stencil.size; ++j)
        if (sb.stencil.w[i] != 0 && sb.stencil.w[j] != 0)
          add(sb.stencil.particle[i], sb.stencil.particle[j], sb.stencil.w[i] * sb.stencil.w[j] * b);
  }
  sys.a.resize(3 * n, 3 * n);
  sys.a.setFromTriplets(t.begin(), t.end());
  Triplets jt;
  for (int p = 0; p < n; ++p) {
    const Eigen::Matrix3d d = sys.a.block(3 * p, 3 * p, 3, 3);
    addBlock(jt, p, p, sys.s[p] * d.inverse() * sys.s[p]);
  }
  sys.jacobi.resize(3 * n, 3 * n);
  sys.jacobi.setFromTriplets(jt.begin(), jt.end());
  CoarseCorrection coarse;
  coarse.setUp(m, filter);
  sys.aggregate.assign(coarse.aggregates(), coarse.aggregates() + n);
  sys.aggregates = coarse.aggregateCount();
  return sys;
}

// W = S Z, each aggregate's columns orthonormalised; rotations: six columns an aggregate instead of three.
SparseMatrix coarseSpace(const System& sys, bool rotations) {
  const int k = rotations ? 6 : 3, aggs = sys.aggregates;
  std::vector<Vec3> centre(aggs, Vec3::Zero());
  std::vector<double> radius(aggs, 0);
  std::vector<int> size(aggs, 0);
  for (int p = 0; p < sys.n; ++p) centre[sys.aggregate[p]] += sys.x[p], ++size[sys.aggregate[p]];
  for (int i = 0; i < aggs; ++i) centre[i] /= std::max(size[i], 1);
  for (int p = 0; p < sys.n; ++p) radius[sys.aggregate[p]] += (sys.x[p] - centre[sys.aggregate[p]]).squaredNorm();
  for (int i = 0; i < aggs; ++i) radius[i] = std::sqrt(radius[i] / std::max(size[i], 1)) + 1e-300;
  const auto z = [&](int p) {
    Eigen::MatrixXd zp = Eigen::MatrixXd::Zero(3, k);
    zp.leftCols<3>().setIdentity();
    if (rotations) {
      const Vec3 d = (sys.x[p] - centre[sys.aggregate[p]]) / radius[sys.aggregate[p]];
      for (int c = 0; c < 3; ++c) zp.col(3 + c) = Vec3::Unit(c).cross(d);
    }
    return Eigen::MatrixXd(sys.s[p] * zp);
  };
  std::vector<Eigen::MatrixXd> gram(aggs, Eigen::MatrixXd::Zero(k, k));
  for (int p = 0; p < sys.n; ++p) {
    const Eigen::MatrixXd w = z(p);
    gram[sys.aggregate[p]] += w.transpose() * w;
  }
  std::vector<Eigen::MatrixXd> basis(aggs);
  std::vector<int> first(aggs + 1, 0);
  for (int i = 0; i < aggs; ++i) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram[i]);
    const double largest = eigen.eigenvalues().maxCoeff();
    std::vector<Eigen::VectorXd> kept;
    for (int c = 0; c < k; ++c)
      if (eigen.eigenvalues()[c] > 1e-9 * largest)
        kept.push_back(eigen.eigenvectors().col(c) / std::sqrt(eigen.eigenvalues()[c]));
    basis[i].resize(k, int(kept.size()));
    for (std::size_t c = 0; c < kept.size(); ++c) basis[i].col(int(c)) = kept[c];
    first[i + 1] = first[i] + int(kept.size());
  }
  Triplets t;
  for (int p = 0; p < sys.n; ++p) {
    const int i = sys.aggregate[p];
    const Eigen::MatrixXd w = z(p) * basis[i];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < w.cols(); ++c)
        if (w(r, c) != 0) t.emplace_back(3 * p + r, first[i] + c, w(r, c));
  }
  SparseMatrix out(3 * sys.n, first[aggs]);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

// (I - omega B A^) W with omega = 4 / (3 rho(B A^)).
SparseMatrix smoothed(const System& sys, const SparseMatrix& w) {
  std::mt19937 random(2);
  std::normal_distribution<double> normal;
  VecX v(3 * sys.n);
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = normal(random);
  v = sys.jacobi * v;
  double rho = 0;
  for (int k = 0; k < 40; ++k) {
    const VecX next = sys.jacobi * (sys.a * v);
    rho = next.norm() / v.norm();
    v = next / next.norm();
  }
  const double omega = 4 / (3 * rho);
  SparseMatrix aw = sys.a * w;
  SparseMatrix baw = sys.jacobi * aw;
  SparseMatrix p = w - omega * baw;
  p.prune(0.0);
  return p;
}

struct Coarse {
  SparseMatrix w;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt;
  long factor_entries = 0;  // nonzeros of L (Eigen's AMD order): the coarse solve's cost
  Coarse(const System& sys, SparseMatrix space) : w(std::move(space)) {
    const SparseMatrix c = SparseMatrix(w.transpose() * (sys.a * w));
    ldlt.compute(c);
    factor_entries = ldlt.matrixL().nestedExpression().nonZeros();
  }
  VecX operator()(const VecX& r) const { return w * ldlt.solve(VecX(w.transpose() * r)); }
};

// Preconditioned CG on A^ d = r0 from 0 until |r| <= threshold; returns the iterations (20000: did not converge).
int iterations(const SparseMatrix& a, const VecX& r0, double threshold, const Preconditioner& precondition) {
  VecX x = VecX::Zero(r0.size()), r = r0, z = precondition(r), p = z;
  double rz = r.dot(z);
  int k = 0;
  for (; r.norm() > threshold && k < 20000; ++k) {
    const VecX q = a * p;
    const double alpha = rz / p.dot(q);
    x += alpha * p;
    r -= alpha * q;
    z = precondition(r);
    const double next = r.dot(z);
    p = z + (next / rz) * p;
    rz = next;
  }
  return k;
}

// The coarse spaces' preconditioners: B + Q for translations, rotations, and both smoothed.
struct Candidates {
  static constexpr int kCount = 5;
  static constexpr const char* kNames[kCount] = {"B", "B+Q transl.", "B+Q transl.+rot.", "B+Q transl. smoothed",
                                                 "B+Q transl.+rot. smoothed"};
  std::unique_ptr<Coarse> q[4];
  explicit Candidates(const System& sys, bool smooth = true) {
    const SparseMatrix w3 = coarseSpace(sys, false), w6 = coarseSpace(sys, true);
    q[0] = std::make_unique<Coarse>(sys, w3);
    q[1] = std::make_unique<Coarse>(sys, w6);
    if (smooth)
      q[2] = std::make_unique<Coarse>(sys, smoothed(sys, w3)), q[3] = std::make_unique<Coarse>(sys, smoothed(sys, w6));
  }
  // Iterations under each (-1: not run).
  std::vector<int> run(const System& sys, const VecX& r0, double threshold) const {
    std::vector<int> out{iterations(sys.a, r0, threshold, [&](const VecX& r) { return VecX(sys.jacobi * r); })};
    for (const auto& c : q)
      out.push_back(c ? iterations(sys.a, r0, threshold, [&](const VecX& r) { return VecX(sys.jacobi * r + (*c)(r)); })
                      : -1);
    return out;
  }
};

void stiffClothTable(int side) {
  std::printf("CG iterations to relative residual 1e-3, %d x %d cloth, ks 1e5, dt 1/60, exact coarse solves\n\n", side,
              side);
  std::printf(
      "| t (s) | block-Jacobi B | additive B + Q (the solver's) | B then Q: B + Q (I - A B) | balancing "
      "Q + (I - Q A) B (I - A Q) | V(1,1): B, Q, B | B + Q, rotations too | B + Q smoothed | B + Q, rotations too, "
      "smoothed |\n|---|---|---|---|---|---|---|---|---|\n");
  long entries[4] = {};
  int unknowns[4] = {};
  for (const double t : {0.1, 0.25, 0.5, 0.9}) {
    ClothParams p;
    p.nx = p.ny = side;
    p.ks = 1e5;
    p.pinned = clothPinSet("corners", p.nx, p.ny);
    MassSpringSystem system;
    system.addBody(buildCloth("cloth", p));
    const double h = 1.0 / 60;
    Simulation sim(system, makeIntegrator("backward-euler"), h);
    sim.advanceTo(t);
    const ForceJacobian& jacobian = *system.forceJacobian();
    PairBlockMatrix blocks;
    blocks.reset(jacobian.jacobianPattern());
    jacobian.fillJacobian(0, sim.x(), sim.v(), h * h, h, blocks, nullptr, nullptr);
    const int n = system.particleCount();
    for (int i = 0; i < n; ++i) blocks.self()[i] += jacobian.mass()[i];
    ParticleFilter filter;
    filter.reset(jacobian.inverseMass());
    const System sys = capture(blocks, filter, sim.x());
    std::mt19937 random(1);
    std::normal_distribution<double> normal;
    VecX b(3 * n);
    for (int i = 0; i < n; ++i)
      particle(b, i) = sys.s[i] * Vec3(0.01 * normal(random), -9.81 * h + 0.01 * normal(random), 0.01 * normal(random));
    const Candidates c(sys);
    const SparseMatrix& a = sys.a;
    const Coarse& q = *c.q[0];
    const auto jacobi = [&](const VecX& r) { return VecX(sys.jacobi * r); };
    const std::vector<Preconditioner> others = {
        [&](const VecX& r) {
          const VecX z = jacobi(r);
          return VecX(z + q(r - a * z));
        },
        [&](const VecX& r) {
          const VecX x = q(r), y = jacobi(r - a * x);
          return VecX(x + y - q(a * y));
        },
        [&](const VecX& r) {
          const VecX z1 = jacobi(r), z2 = z1 + q(r - a * z1);
          return VecX(z2 + jacobi(r - a * z2));
        },
    };
    const std::vector<int> its = c.run(sys, b, 1e-3 * b.norm());
    std::printf("| %.2f | %d | %d |", t, its[0], its[1]);
    for (const Preconditioner& m : others) std::printf(" %d |", iterations(a, b, 1e-3 * b.norm(), m));
    std::printf(" %d | %d | %d |\n", its[2], its[3], its[4]);
    for (int k = 0; k < 4; ++k) entries[k] = c.q[k]->factor_entries, unknowns[k] = int(c.q[k]->w.cols());
  }
  std::printf("\nCoarse unknowns and nonzeros of its LDL^T factor (Eigen's AMD order):");
  for (int k = 0; k < 4; ++k) std::printf(" %s %d, %ld;", Candidates::kNames[k + 1], unknowns[k], entries[k]);
  std::printf(
      "\nA product with A costs about a CG iteration's product; B then Q needs one more per iteration, "
      "balancing and V(1,1) two (less where A Q's product runs over the aggregates' boundary pairs only).\n");
}

// The solver's systems, captured in the steps measured.
struct Tapped {
  const Simulation* sim = nullptr;
  bool smooth = true;
  std::vector<long> sums = std::vector<long>(Candidates::kCount, 0);
  std::vector<long> step = std::vector<long>(Candidates::kCount, 0);
  long entries[4] = {}, unknowns[4] = {};
  int solves = 0;
};
Tapped* tapped = nullptr;

void tap(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, const VecX& x0, double tolerance) {
  const System sys = capture(a, s, tapped->sim->x());
  VecX z(b.size()), ax, az;
  for (int p = 0; p < sys.n; ++p) particle(z, p) = particle(x0, p) - sys.s[p] * particle(x0, p);
  a.multiply(x0, ax, false);
  a.multiply(z, az, false);
  VecX r0(b.size()), rhs(b.size());
  for (int p = 0; p < sys.n; ++p) {
    particle(r0, p) = sys.s[p] * (particle(b, p) - particle(ax, p));
    particle(rhs, p) = sys.s[p] * (particle(b, p) - particle(az, p));
  }
  const Candidates c(sys, tapped->smooth);
  const std::vector<int> its = c.run(sys, r0, tolerance * rhs.norm());
  ++tapped->solves;
  for (int k = 0; k < Candidates::kCount; ++k) tapped->step[k] += its[k];
  for (int k = 0; k < 4; ++k)
    if (c.q[k]) tapped->entries[k] += c.q[k]->factor_entries, tapped->unknowns[k] += c.q[k]->w.cols();
}

int solverSystems(int argc, char** argv) {
  const std::string kind = argv[1];
  const int side = argc > 2 ? std::atoi(argv[2]) : 100;
  const bool contact = kind != "jelly" && argc > 3 && std::atoi(argv[3]) != 0;
  const int steps = std::atoi(argc > (kind == "jelly" ? 3 : 4) ? argv[kind == "jelly" ? 3 : 4] : "10");
  std::unique_ptr<MassSpringSystem> system;
  IntegratorOptions options;
  if (kind == "stacked") {
    system = testing::foldedCloth(side, contact, 4, 0.5, 0);
    options.cg_max_iterations = 20000;
  } else if (kind == "folded") {
    system = testing::foldedCloth(side, contact);
  } else if (kind == "jelly") {
    JellyParams p;
    p.n = side;
    p.ks = 1e5;
    p.center = Vec3(0, 2.2, 0);
    system = std::make_unique<MassSpringSystem>();
    system->addBody(buildJelly("jelly", p));
    system->addCollider(
        std::make_unique<PlaneCollider>("floor", ContactParams{0, 0.5, 0.005}, Vec3::Zero(), Vec3::UnitY()));
  } else {
    std::fprintf(stderr, "preconditioner_study: unknown case '%s' (stacked, folded, jelly)\n", kind.c_str());
    return 2;
  }
  const double dt = 1.0 / 60;
  Simulation sim(*system, makeIntegrator("backward-euler", options), dt);
  sim.advanceTo(0.5);
  Tapped t;
  t.sim = &sim;
  t.smooth = std::getenv("NO_SMOOTH") == nullptr;
  tapped = &t;
  setPcgSystemTap(tap);
  std::printf("%s %d%s, backward Euler at 1/60, steps %ld to %ld: CG iterations a step, exact coarse solves\n",
              kind.c_str(), side, kind == "jelly" ? "^3" : (contact ? " x side, self-contact" : " x side"),
              sim.steps() + 1, sim.steps() + steps);
  std::printf("| step | solves | the solver's |");
  for (const char* name : Candidates::kNames) std::printf(" %s |", name);
  std::printf("\n");
  std::vector<long> total(Candidates::kCount, 0);
  long solver_total = 0;
  for (int k = 0; k < steps; ++k) {
    std::fill(t.step.begin(), t.step.end(), 0);
    const int solves = t.solves;
    if (sim.advanceTo(sim.time() + dt)) return std::printf("the run stopped\n"), 3;
    const int own = sim.integrator().stats().last_cg_iterations;
    solver_total += own;
    std::printf("| %ld | %d | %d |", sim.steps(), t.solves - solves, own);
    for (int c = 0; c < Candidates::kCount; ++c) std::printf(" %ld |", t.step[c]), total[c] += t.step[c];
    std::printf("\n");
    std::fflush(stdout);
  }
  std::printf("| mean a step | %.2f | %.1f |", double(t.solves) / steps, double(solver_total) / steps);
  for (int c = 0; c < Candidates::kCount; ++c) std::printf(" %.1f |", double(total[c]) / steps);
  std::printf("\nCoarse unknowns and nonzeros of its LDL^T factor (Eigen's AMD order), a solve:");
  for (int k = 0; k < 4; ++k)
    std::printf(" %s %ld, %ld;", Candidates::kNames[k + 1], t.unknowns[k] / t.solves, t.entries[k] / t.solves);
  std::printf("\n");
  setPcgSystemTap(nullptr);
  return 0;
}

}  // namespace
}  // namespace wobble

int main(int argc, char** argv) {
  using namespace wobble;
  if (argc > 1 && !std::isdigit(static_cast<unsigned char>(argv[1][0]))) return solverSystems(argc, argv);
  stiffClothTable(argc > 1 ? std::atoi(argv[1]) : 100);
}
