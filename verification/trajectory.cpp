// Recording a verification run and the measures taken from its trajectory.
#include "verification/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace latticedyn {

double Trajectory::at(int joint, int component, double t) const {
  if (time.empty() || t < time.front() - 1e-12 || t > time.back() + 1e-12)
    throw std::out_of_range("time outside the recorded range");
  const auto it = std::lower_bound(time.begin(), time.end(), t - 1e-12);
  const std::size_t k = static_cast<std::size_t>(it - time.begin());
  if (k == 0 || std::abs(time[k] - t) < 1e-12) return joints[k][joint](component);
  const double w = (t - time[k - 1]) / (time[k] - time[k - 1]);
  return (1 - w) * joints[k - 1][joint](component) + w * joints[k][joint](component);
}

double Trajectory::period(int joint, int component, double from) const {
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < time.size(); ++i)
    if (time[i] >= from) {
      lo = std::min(lo, joints[i][joint](component));
      hi = std::max(hi, joints[i][joint](component));
    }
  const double mid = 0.5 * (lo + hi);
  std::vector<double> crossings;
  for (std::size_t i = 1; i < time.size(); ++i) {
    if (time[i - 1] < from) continue;
    const double a = joints[i - 1][joint](component) - mid, b = joints[i][joint](component) - mid;
    if (a < 0 && b >= 0) crossings.push_back(time[i - 1] + (time[i] - time[i - 1]) * (-a) / (b - a));
  }
  if (crossings.size() < 2) return 0.0;
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

double Trajectory::damping_ratio(int joint, int component, double from, double* omega_n) const {
  std::vector<double> te, xe;  // extrema
  for (std::size_t i = 1; i + 1 < time.size(); ++i) {
    if (time[i - 1] < from) continue;
    const double a = joints[i - 1][joint](component), b = joints[i][joint](component), c = joints[i + 1][joint](component);
    if (!((b > a && b >= c) || (b < a && b <= c))) continue;
    // Vertex of the parabola through the three samples (uniform spacing h assumed locally).
    const double h = 0.5 * (time[i + 1] - time[i - 1]), curvature = a - 2 * b + c;
    const double shift = curvature != 0 ? 0.5 * (a - c) / curvature : 0.0;
    te.push_back(time[i] + shift * h);
    xe.push_back(b - 0.25 * (a - c) * shift);
  }
  if (te.size() < 4) return std::numeric_limits<double>::quiet_NaN();
  // ln |x_{k+1} - x_k| = const - sigma t, least squares over the half cycles.
  const std::size_t n = te.size() - 1;
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = 0.5 * (te[k] + te[k + 1]), y = std::log(std::abs(xe[k + 1] - xe[k]));
    st += t, sy += y, stt += t * t, sty += t * y;
  }
  const double sigma = -(n * sty - st * sy) / (n * stt - st * st);
  const double half_period = (te.back() - te.front()) / static_cast<double>(n);
  const double omega_d = std::numbers::pi / half_period;
  if (omega_n) *omega_n = std::sqrt(sigma * sigma + omega_d * omega_d);
  return sigma / std::sqrt(sigma * sigma + omega_d * omega_d);
}

double Trajectory::energy_drift() const {
  if (energy.empty()) return 0.0;
  double drift = 0.0, kmax = 0.0;
  for (std::size_t i = 0; i < energy.size(); ++i) {
    drift = std::max(drift, std::abs(energy[i] - energy.front()));
    kmax = std::max(kmax, kinetic[i]);
  }
  return kmax > 0 ? drift / kmax : drift;
}

TrajectoryRecorder::TrajectoryRecorder(SystemAssembler& sa, double interval, Trajectory* out)
    : sa_(sa), state_(sa.model(), sa.dofs()), interval_(interval), out_(out) {
  if (EnergyLedger::applies(sa.model())) ledger_.emplace(sa.model());
}

PetscErrorCode TrajectoryRecorder::record(double t, Vec U, Vec V, Parametrization param) {
  PetscFunctionBeginUser;
  PetscCall(sa_.gather(t, U, V, nullptr, param, &state_));
  last_recorded_ = t;
  if (sa_.dofs().rank() == 0) {
    std::vector<Vec3> joints;
    std::vector<Mat3> frames;
    for (std::size_t j = 0; j < sa_.model().joints.size(); ++j) {
      const auto [r, R] = state_.joint_frame_of(static_cast<int>(j));
      joints.push_back(r);
      frames.push_back(R);
    }
    const ElementEnergy e = state_.energy();
    out_->time.push_back(t);
    out_->joints.push_back(std::move(joints));
    out_->frames.push_back(std::move(frames));
    out_->energy.push_back(e.kinetic + e.gravity_potential + e.strain + e.fluid);
    out_->kinetic.push_back(e.kinetic);
    out_->violation.push_back(state_.max_constraint_violation().first);
    std::vector<double> axial(sa_.model().elements.size());
    for (std::size_t e = 0; e < axial.size(); ++e)
      axial[e] = state_.axial_force(static_cast<int>(e)).value_or(std::numeric_limits<double>::quiet_NaN());
    out_->axial.push_back(std::move(axial));
    if (out_->record_member_peaks) {
      auto& peaks = out_->member_peaks;
      peaks.resize(sa_.model().elements.size());
      ElementOutput o;
      for (std::size_t e = 0; e < peaks.size(); ++e) {
        const int ei = static_cast<int>(e);
        sa_.model().elements[e].element->output(state_.element_slots(ei), state_.context(), o);
        peaks[e].resize(o.members.size(), 0.0);
        for (std::size_t m = 0; m < o.members.size(); ++m) peaks[e][m] = std::max(peaks[e][m], o.members[m].von_mises);
      }
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode TrajectoryRecorder::on_step(const StepInfo& info) {
  PetscFunctionBeginUser;
  const double eps = 1e-9 * std::max(1.0, std::abs(info.time));
  if (ledger_) {
    PetscCall(sa_.gather(info.time, info.U, info.V, info.A, info.param, &state_));
    if (sa_.dofs().rank() == 0 && (!ledger_->started() || info.time > ledger_->account().time)) {
      PetscCallCXX(ledger_->record(state_));
      out_->energy_account = ledger_->account();
    }
  }
  if (info.step == 0 || info.time >= next_ - eps) {
    PetscCall(record(info.time, info.U, info.V, info.param));
    if (interval_ > 0) next_ = (std::floor((info.time + eps) / interval_) + 1) * interval_;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode TrajectoryRecorder::finish(double t, Vec U, Vec V) {
  PetscFunctionBeginUser;
  if (last_recorded_ != t) PetscCall(record(t, U, V, Parametrization::rotation_vector_rates));
  PetscCall(sa_.gather(t, U, V, nullptr, Parametrization::rotation_vector_rates, &state_));
  if (sa_.dofs().rank() == 0) {
    out_->final_state = std::make_unique<ModelState>(sa_.model(), *out_->dofs);
    out_->final_state->set(t, state_.coordinates(), {}, {}, Parametrization::rotation_vector_rates);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode run_and_record(const std::string& model_path, MPI_Comm comm, Trajectory* trajectory,
                              SimulationOutcome* outcome, const std::string& results_directory,
                              const std::vector<KeyOverride>& overrides) {
  PetscFunctionBeginUser;
  trajectory->simulation = std::make_unique<Simulation>(read_simulation(model_path, overrides));
  Simulation& sim = *trajectory->simulation;
  SystemAssembler sa(sim.model, comm);
  trajectory->dofs = std::make_unique<DofMap>(sa.dofs());
  Vec U, V;
  PetscCall(sa.create_vector(&U));
  PetscCall(sa.create_vector(&V));
  PetscCall(sa.initial_state(U, V));
  {
    ModelState s0(sim.model, sa.dofs());
    PetscCall(sa.gather(0.0, U, V, nullptr, Parametrization::rotation_vector_rates, &s0));
    if (sa.dofs().rank() == 0)
      for (std::size_t j = 0; j < sim.model.joints.size(); ++j) trajectory->joints0.push_back(s0.joint_position(static_cast<int>(j)));
  }
  TrajectoryRecorder recorder(sa, sim.output.interval, trajectory);
  std::unique_ptr<ResultWriter> writer;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (!results_directory.empty() && rank == 0) {
    ResultWriterOptions o;
    o.directory = results_directory;
    o.base_name = sim.output.name;
    o.probe_joints = sim.output.probe_joints;
    writer = std::make_unique<ResultWriter>(sim.model, o);
  }
  const double t_end = sim.run_dynamics ? sim.dynamics.t_end : sim.statics.time;
  OutputObserver output(sa, writer.get(), sim.output.interval, t_end);
  ObserverList observers;
  observers.add(&recorder);
  if (!results_directory.empty()) observers.add(&output);
  const bool statics = sim.run_static || !sim.run_dynamics;
  PetscCall(simulate(sim, sa, U, V, statics, sim.run_dynamics, &observers, outcome));
  const double t = outcome->dynamics_run ? outcome->dynamics.time_reached : sim.statics.time;
  PetscCall(recorder.finish(t, U, V));
  if (!results_directory.empty()) PetscCall(output.finish(t, U, V, Parametrization::rotation_vector_rates));
  PetscCall(VecDestroy(&U));
  PetscCall(VecDestroy(&V));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
