// Static equilibrium paths through limit points: Crisfield's cylindrical arc-length method on the
// load factor lambda of the model's gravity and nodal loads, for limit loads and snap-through.
#pragma once

#include "assembly/system_assembler.hpp"

#include <petscksp.h>

#include <functional>
#include <string>
#include <vector>

namespace latticedyn {

struct PathSettings {
  /// Length of the first arc in the coordinates (m and rad, multipliers left out); 0: a tenth of
  /// the linear response to the full loads, |K^-1 f|.
  double arc_length = 0.0;
  int max_steps = 100;
  double max_load_factor = 1.0;    ///< stop once lambda exceeds it
  double min_load_factor = -1e30;  ///< stop once lambda falls below it (after the path turned back)
  int max_iterations = 20;         ///< Newton iterations per arc
  int target_iterations = 5;       ///< the arc grows or shrinks by sqrt(target / used) (Crisfield 1981)
  double max_arc_factor = 10.0;    ///< the arc stays within [1/1024, max_arc_factor] x the first one
  double tolerance = 1e-8;         ///< converged when |R| <= tolerance |f| (f the reference loads)
  double time = 0.0;               ///< time at which drives and loads are evaluated
  bool valid() const;
};

/// A converged point of the path.
struct PathPoint {
  int step = 0;
  double load_factor = 0.0;
  int iterations = 0;
  double arc_length = 0.0;
  Vec U = nullptr;  ///< the coordinates and multipliers there (the solver's; valid during the callback)
};

struct PathReport {
  bool completed = false;  ///< reached max_load_factor, min_load_factor or max_steps
  int steps = 0;           ///< converged points after the start
  int newton_iterations = 0;
  int cuts = 0;            ///< arcs halved after a failed corrector
  double max_load_factor = 0.0;  ///< the largest lambda on the path
  std::string message;     ///< why it stopped
};

/// Where a path's load factor turns: a local maximum (a limit load) or minimum.
struct LimitPoint {
  std::size_t index = 0;  ///< into the factors, i.e. the path point
  bool maximum = true;
};
std::vector<LimitPoint> limit_points(const std::vector<double>& factors);

/// Traces R(U, lambda) = F_int(U) + G^T mu - lambda f(U) = 0, g(U) = 0 from the state U (its
/// load factor `lambda0`, 0 for the unloaded start) under the cylindrical constraint
/// |Delta U|^2 = Delta s^2 over the coordinates (Crisfield, Comput. Struct. 13 (1981) 55-62; Non-linear
/// Finite Element Analysis of Solids and Structures, vol. 1, 1991, 9.3): per corrector iteration
/// the two solves K dU_R = -R, K dU_f = f and the root of the quadratic for d lambda closest in
/// direction to the last increment. The predictor's sign follows the previous increment (Feng et
/// al. 1996), so the path turns at limit points and snap-backs. Failed correctors halve the arc.
class ArcLengthSolver {
 public:
  ArcLengthSolver(SystemAssembler& assembler, PathSettings settings);
  ~ArcLengthSolver();
  ArcLengthSolver(const ArcLengthSolver&) = delete;
  ArcLengthSolver& operator=(const ArcLengthSolver&) = delete;

  /// U: the start in, the last converged point out. `on_point` (may be empty) hears of the start
  /// (step 0) and every converged point. Collective.
  PetscErrorCode trace(Vec U, double lambda0, const std::function<PetscErrorCode(const PathPoint&)>& on_point,
                       PathReport* report);

 private:
  EvaluationSettings evaluation(double lambda) const;
  PetscErrorCode residual(Vec U, double lambda, Vec R);
  PetscErrorCode reference_load(Vec U, Vec f);  ///< f = R(U, 0) - R(U, 1)
  PetscErrorCode factor(Vec U, double lambda);
  double coordinate_dot(Vec a, Vec b) const;

  SystemAssembler& sa_;
  PathSettings settings_;
  Mat J_ = nullptr;
  KSP ksp_ = nullptr;
  Vec mask_ = nullptr;  ///< 1 on coordinates, 0 on multipliers
  Vec work_ = nullptr;
};

}  // namespace latticedyn
