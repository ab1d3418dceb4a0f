// Linearized buckling with SLEPc: K0 phi = lambda (K0 - K1) phi by shift-and-invert near zero.
#include "timestepping/buckling_analysis.hpp"

#include "timestepping/eigen_pencil.hpp"

#include <algorithm>
#include <cmath>

namespace latticedyn {

namespace {
// Largest relative residual |K0 phi - lambda B phi| / (|lambda| |phi|) of a mode that is kept.
constexpr double kMaxResidual = 1e-3;
}  // namespace

BucklingAnalysis::BucklingAnalysis(SystemAssembler& sa, BucklingSettings settings) : sa_(sa), settings_(settings) {
  PetscCallAbort(sa_.comm(), sa_.create_matrix(&K0_));
  PetscCallAbort(sa_.comm(), sa_.create_matrix(&KG_));
}

BucklingAnalysis::~BucklingAnalysis() {
  MatDestroy(&K0_);
  MatDestroy(&KG_);
}

PetscErrorCode BucklingAnalysis::solve(Vec U0, Vec U1, double t, std::vector<BucklingMode>* modes,
                                       std::string* message) {
  PetscFunctionBeginUser;
  // Velocity variables, as for the natural modes: at an equilibrium the tangent is symmetric in them.
  EvaluationSettings how;
  how.param = Parametrization::velocity_variables;
  const double s = sa_.characteristic_stiffness();
  how.constraint_scale = s;
  how.load_scale = 0.0;
  PetscCall(sa_.jacobian(EvaluationPoint{U0, nullptr, nullptr, nullptr, t, t}, how, 1.0, 0.0, 0.0, K0_));
  how.load_scale = 1.0;
  PetscCall(sa_.jacobian(EvaluationPoint{U1, nullptr, nullptr, nullptr, t, t}, how, 1.0, 0.0, 0.0, KG_));
  // B = K0 - K1 = -(geometric stiffness of the reference loads).
  PetscCall(MatAYPX(KG_, -1.0, K0_, SAME_NONZERO_PATTERN));
  PetscCall(scale_multiplier_columns(sa_, s, {K0_, KG_}));

  // K0 - K1 is indefinite and singular (zero wherever no stress acts), and the tangents are not
  // symmetric away from an equilibrium (follower loads, U0 under prestress): a general pencil.
  // A shift just below zero keeps K0 - sigma B regular for a mechanism held by its loads alone
  // (a hanging pendulum: lambda = 0 buckles it, K0 alone is singular).
  EPS eps;
  PetscCall(create_shift_invert_eps(sa_.comm(), K0_, KG_, EPS_GNHEP, -1e-6, search_count(sa_, settings_.modes), settings_.tolerance, &eps));
  PetscCall(EPSSolve(eps));
  PetscInt converged;
  PetscCall(EPSGetConverged(eps, &converged));

  std::vector<BucklingMode> found;
  int complex_pairs = 0, inaccurate = 0;
  Vec xi;
  PetscCall(MatCreateVecs(K0_, &xi, nullptr));
  for (PetscInt i = 0; i < converged; ++i) {
    PetscScalar re, im;
    BucklingMode m;
    PetscCall(MatCreateVecs(K0_, &m.vector, nullptr));
    PetscCall(EPSGetEigenpair(eps, i, &re, &im, m.vector, xi));
    // A load factor is real; an eigenvalue with an imaginary part above round-off is a flutter
    // pair of a non-conservative load, not a divergence instability.
    if (std::abs(PetscImaginaryPart(re) + im) > 1e-8 * std::max(1.0, std::abs(PetscRealPart(re)))) {
      ++complex_pairs;
      PetscCall(VecDestroy(&m.vector));
      continue;
    }
    PetscReal err;
    PetscCall(EPSComputeError(eps, i, EPS_ERROR_RELATIVE, &err));
    // Converged in the shifted-and-inverted operator but not a solution of the pencil: K0 is
    // (nearly) singular, a mechanism that only its loads hold (a pendulum), where linearized
    // buckling has no meaning.
    if (!(err <= kMaxResidual)) {
      ++inaccurate;
      PetscCall(VecDestroy(&m.vector));
      continue;
    }
    m.factor = PetscRealPart(re);
    m.residual = err;
    // The largest entry 1, with a positive sign, for a repeatable drawing.
    PetscReal lo, hi;
    PetscCall(VecMin(m.vector, nullptr, &lo));
    PetscCall(VecMax(m.vector, nullptr, &hi));
    const double scale = hi >= -lo ? hi : lo;
    if (scale != 0) PetscCall(VecScale(m.vector, 1.0 / scale));
    found.push_back(m);
  }
  PetscCall(VecDestroy(&xi));
  PetscCall(EPSDestroy(&eps));
  std::sort(found.begin(), found.end(),
            [](const BucklingMode& a, const BucklingMode& b) { return std::abs(a.factor) < std::abs(b.factor); });
  const int wanted = std::min<int>(settings_.modes, static_cast<int>(found.size()));
  for (std::size_t i = static_cast<std::size_t>(wanted); i < found.size(); ++i) PetscCall(VecDestroy(&found[i].vector));
  found.resize(static_cast<std::size_t>(wanted));
  *modes = std::move(found);
  if (message) {
    *message = std::to_string(converged) + " eigenpairs converged, " + std::to_string(settings_.modes) + " wanted";
    if (complex_pairs > 0)
      *message += ", " + std::to_string(complex_pairs) + " complex (flutter of a non-conservative load) left out";
    if (inaccurate > 0)
      *message += ", " + std::to_string(inaccurate) +
                  " with a residual above 1e-3 left out (is the unloaded model a mechanism, held by its loads alone?)";
  }
  PetscFunctionReturn(0);
}

void destroy_modes(std::vector<BucklingMode>& modes) {
  for (BucklingMode& m : modes) VecDestroy(&m.vector);
  modes.clear();
}

}  // namespace latticedyn
