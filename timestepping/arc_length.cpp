// Crisfield's cylindrical arc-length method: predictor along the tangent, corrector on the
// cylinder |Delta U| = Delta s, arcs adapted to the Newton iterations they take.
#include "timestepping/arc_length.hpp"

#include "timestepping/native_lu.hpp"
#include "timestepping/prefixed_options.hpp"
#include "timestepping/solver_setup.hpp"

#include <algorithm>
#include <cmath>

namespace latticedyn {

namespace {
constexpr int kMaxCuts = 10;  // 2^-10 of an arc
}  // namespace

std::vector<LimitPoint> limit_points(const std::vector<double>& f) {
  std::vector<LimitPoint> points;
  for (std::size_t k = 1; k + 1 < f.size(); ++k) {
    if (f[k] > f[k - 1] && f[k] >= f[k + 1]) points.push_back({k, true});
    if (f[k] < f[k - 1] && f[k] <= f[k + 1]) points.push_back({k, false});
  }
  return points;
}

bool PathSettings::valid() const {
  return arc_length >= 0 && max_steps >= 1 && max_iterations >= 1 && target_iterations >= 1 && max_arc_factor >= 1 &&
         tolerance > 0 && min_load_factor < max_load_factor;
}

ArcLengthSolver::ArcLengthSolver(SystemAssembler& sa, PathSettings settings) : sa_(sa), settings_(settings) {
  MPI_Comm comm = sa_.comm();
  PetscCallAbort(comm, sa_.create_matrix(&J_));
  PetscCallAbort(comm, sa_.create_vector(&mask_));
  PetscCallAbort(comm, VecDuplicate(mask_, &work_));
  PetscCallAbort(comm, fill_by_row_kind(sa_, 1.0, 0.0, mask_));
  const PrefixedOptions options(kStaticPrefix);
  PetscCallAbort(comm, KSPCreate(comm, &ksp_));
  PetscCallAbort(comm, set_direct_solver_defaults(ksp_));
  PetscCallAbort(comm, KSPSetFromOptions(ksp_));
}

ArcLengthSolver::~ArcLengthSolver() {
  KSPDestroy(&ksp_);
  MatDestroy(&J_);
  VecDestroy(&mask_);
  VecDestroy(&work_);
}

EvaluationSettings ArcLengthSolver::evaluation(double lambda) const {
  EvaluationSettings how;
  how.param = Parametrization::rotation_vector_rates;
  how.load_scale = lambda;
  how.constraint_scale = sa_.characteristic_stiffness();  // as the static solver's rows
  return how;
}

PetscErrorCode ArcLengthSolver::residual(Vec U, double lambda, Vec R) {
  PetscFunctionBeginUser;
  PetscBool finite;
  PetscCall(sa_.residual(EvaluationPoint{U, nullptr, nullptr, nullptr, settings_.time, settings_.time}, evaluation(lambda),
                         R, &finite));
  if (!finite) PetscCall(VecSet(R, NAN));
  PetscFunctionReturn(0);
}

PetscErrorCode ArcLengthSolver::reference_load(Vec U, Vec f) {
  PetscFunctionBeginUser;
  PetscCall(residual(U, 0.0, f));
  PetscCall(residual(U, 1.0, work_));
  PetscCall(VecAXPY(f, -1.0, work_));
  PetscFunctionReturn(0);
}

PetscErrorCode ArcLengthSolver::factor(Vec U, double lambda) {
  PetscFunctionBeginUser;
  PetscBool reset;
  PetscCall(recover_from_failed_factorisation(ksp_, &reset));
  PetscCall(sa_.jacobian(EvaluationPoint{U, nullptr, nullptr, nullptr, settings_.time, settings_.time},
                         evaluation(lambda), 1.0, 0.0, 0.0, J_));
  PetscCall(KSPSetOperators(ksp_, J_, J_));
  PetscFunctionReturn(0);
}

double ArcLengthSolver::coordinate_dot(Vec a, Vec b) const {
  PetscScalar d = 0.0;
  PetscCallAbort(sa_.comm(), VecPointwiseMult(work_, a, mask_));
  PetscCallAbort(sa_.comm(), VecDot(work_, b, &d));
  return PetscRealPart(d);
}

PetscErrorCode ArcLengthSolver::trace(Vec U, double lambda0, const std::function<PetscErrorCode(const PathPoint&)>& on_point,
                                      PathReport* report) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kStaticPrefix);
  PathReport rep;
  double lambda = lambda0;
  rep.max_load_factor = lambda;
  if (on_point) PetscCall(on_point(PathPoint{0, lambda, 0, 0.0, U}));
  Vec f, tangent, dUf, dUr, R, DU, DU_prev, Utrial;
  for (Vec* v : {&f, &tangent, &dUf, &dUr, &R, &DU, &DU_prev, &Utrial}) PetscCall(VecDuplicate(U, v));
  PetscCall(VecZeroEntries(DU_prev));
  bool have_previous = false;
  KSPConvergedReason reason;
  // Solves K x = b with the current factorisation; false if the solve failed.
  const auto solve = [&](Vec b, Vec x, bool* ok) {
    PetscFunctionBeginUser;
    PetscCall(KSPSolve(ksp_, b, x));
    PetscCall(KSPGetConvergedReason(ksp_, &reason));
    PetscReal norm;
    PetscCall(VecNorm(x, NORM_2, &norm));
    *ok = reason >= 0 && std::isfinite(norm);
    PetscFunctionReturn(0);
  };

  double first_arc = settings_.arc_length, arc = 0.0;
  while (rep.steps < settings_.max_steps) {
    // Predictor: along the tangent's response to the reference loads.
    bool ok = true;
    PetscCall(factor(U, lambda));
    PetscCall(reference_load(U, f));
    PetscReal fnorm;
    PetscCall(VecNorm(f, NORM_2, &fnorm));
    if (!(fnorm > 0)) {
      rep.message = "the model has no gravity or nodal loads to scale";
      break;
    }
    PetscCall(solve(f, tangent, &ok));
    if (!ok) {
      rep.message = "the tangent at load factor " + std::to_string(lambda) + " could not be factored (a mechanism?)";
      break;
    }
    const double tangent_norm = std::sqrt(coordinate_dot(tangent, tangent));
    if (arc == 0.0) {
      if (first_arc <= 0.0) first_arc = 0.1 * tangent_norm;
      arc = first_arc;
    }
    // Past a limit point the tangent's response turns against the last increment: so must lambda.
    double sign = 1.0;
    if (have_previous) sign = coordinate_dot(tangent, DU_prev) >= 0 ? 1.0 : -1.0;

    bool converged = false;
    int iterations = 0, cuts = 0;
    double dlambda = 0.0;
    while (!converged && cuts <= kMaxCuts) {
      dlambda = sign * arc / tangent_norm;
      PetscCall(VecCopy(tangent, DU));
      PetscCall(VecScale(DU, dlambda));
      iterations = 0;
      for (; iterations <= settings_.max_iterations; ++iterations) {
        PetscCall(VecWAXPY(Utrial, 1.0, DU, U));
        PetscCall(residual(Utrial, lambda + dlambda, R));
        PetscReal rnorm;
        PetscCall(VecNorm(R, NORM_2, &rnorm));
        if (!std::isfinite(rnorm)) break;  // outside an element's domain: a shorter arc
        if (rnorm <= settings_.tolerance * fnorm) {
          converged = true;
          break;
        }
        if (iterations == settings_.max_iterations) break;
        PetscCall(factor(Utrial, lambda + dlambda));
        PetscCall(VecScale(R, -1.0));
        bool ok_r = true, ok_f = true;
        PetscCall(solve(R, dUr, &ok_r));
        PetscCall(reference_load(Utrial, f));
        PetscCall(solve(f, dUf, &ok_f));
        if (!ok_r || !ok_f) break;
        // |DU + dUr + dl dUf|^2 = arc^2 over the coordinates: a dl^2 + b dl + c = 0.
        PetscCall(VecAXPY(dUr, 1.0, DU));  // dUr := DU + dUr
        const double a = coordinate_dot(dUf, dUf), b = 2 * coordinate_dot(dUf, dUr),
                     c = coordinate_dot(dUr, dUr) - arc * arc;
        const double disc = b * b - 4 * a * c;
        if (!(disc >= 0) || !(a > 0)) break;  // the cylinder is missed: a shorter arc
        const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        const double roots[2] = {q / a, q != 0 ? c / q : -b / (2 * a)};
        // The root whose increment turns least from the current one (Crisfield 1981).
        double best = roots[0], best_cos = -2.0;
        const double du_norm2 = coordinate_dot(DU, DU);
        for (double root : roots) {
          PetscCall(VecWAXPY(R, root, dUf, dUr));  // R is free until the next residual
          const double num = coordinate_dot(R, DU);
          const double den = std::sqrt(std::max(coordinate_dot(R, R) * du_norm2, 1e-300));
          if (num / den > best_cos) {
            best_cos = num / den;
            best = root;
          }
        }
        PetscCall(VecWAXPY(DU, best, dUf, dUr));
        dlambda += best;
      }
      rep.newton_iterations += iterations;
      if (converged) break;
      ++cuts;
      ++rep.cuts;
      arc *= 0.5;
    }
    if (!converged) {
      rep.message = "no equilibrium within the arc at load factor " + std::to_string(lambda) + " after " +
                    std::to_string(kMaxCuts) + " halvings of the arc";
      break;
    }
    PetscCall(VecAXPY(U, 1.0, DU));
    lambda += dlambda;
    PetscCall(VecCopy(DU, DU_prev));
    have_previous = true;
    ++rep.steps;
    rep.max_load_factor = std::max(rep.max_load_factor, lambda);
    if (on_point) PetscCall(on_point(PathPoint{rep.steps, lambda, iterations, arc, U}));
    if (lambda >= settings_.max_load_factor) {
      rep.completed = true;
      rep.message = "reached load factor " + std::to_string(lambda) + " (max_load_factor " +
                    std::to_string(settings_.max_load_factor) + ")";
      break;
    }
    if (lambda <= settings_.min_load_factor) {
      rep.completed = true;
      rep.message = "fell to load factor " + std::to_string(lambda) + " (min_load_factor " +
                    std::to_string(settings_.min_load_factor) + ")";
      break;
    }
    // Next arc from this one's effort, within bounds.
    const double grow = std::sqrt(static_cast<double>(settings_.target_iterations) / std::max(1, iterations));
    arc = std::clamp(arc * std::clamp(grow, 0.25, 2.0), first_arc / 1024, first_arc * settings_.max_arc_factor);
  }
  if (rep.steps >= settings_.max_steps && rep.message.empty()) {
    rep.completed = true;
    rep.message = "max_steps (" + std::to_string(settings_.max_steps) + ") reached at load factor " + std::to_string(lambda);
  }
  for (Vec* v : {&f, &tangent, &dUf, &dUr, &R, &DU, &DU_prev, &Utrial}) PetscCall(VecDestroy(v));
  *report = rep;
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
