// Reduction accuracy of the super truss (thesis 8.2): the same lattice as the unreduced model
// (every member a Timoshenko beam, rigid end sections) and as super truss elements, compared on
// static tip response to each load (8.2.3's equivalent stiffness), the equivalent mass test
// (free-free: twice the kinetic energy of each unit rigid-body velocity, v^T M v / |v|^2, which is
// the mass that 8.2.3's equal end forces or torques accelerate; docs/lattice.md), the lowest
// natural frequencies with mode shapes paired by MAC on the lattice nodes' motion, dynamic tip
// response under self-weight, end torque and angle drive (8.2.1, 8.2.2), member axial forces near
// the root, and the cost of each model.
#include "verification/study.hpp"

#include "elements/super_truss.hpp"
#include "io/model_reader.hpp"
#include "timestepping/modal_analysis.hpp"

#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

namespace latticedyn {

namespace {

enum class Variant { full, reduced };
const char* name_of(Variant v) { return v == Variant::full ? "full" : "reduced"; }

struct Settings {
  std::vector<std::string> bodies;
  std::string root, tip;
  std::vector<std::array<std::string, 2>> splices;
  double force = 1e4, axial_force = 1e5, moment = 1e5, torque = 1e6;
  double self_weight_time = 1.0, torque_time = 2.0, angle_time = 4.0, time_step = 2e-3, window = 0.5;
  double gravity = 9.81;  ///< magnitude for the self-weight tests
  double angle_amplitude = std::numbers::pi / 4;  ///< A of psi = -A (1 - cos(pi t / 5)) (thesis 8-2: pi / 4)
  int modes = 6;
};

Settings read_settings(const InputNode& n) {
  n.allow_only({"bodies", "root", "tip", "splices", "force", "axial_force", "moment", "torque", "self_weight_time",
                "torque_time", "angle_time", "time_step", "window", "modes", "gravity", "angle_amplitude"});
  Settings s;
  for (const InputNode& b : n["bodies"].items()) s.bodies.push_back(b.as_string());
  s.root = n["root"].as_string();
  s.tip = n["tip"].as_string();
  if (auto sp = n.get("splices"))
    for (const InputNode& p : sp->items()) {
      const auto ends = p.items();
      if (ends.size() != 2) p.fail("expected a pair of joints [\"a.2\", \"b.1\"]");
      s.splices.push_back({ends[0].as_string(), ends[1].as_string()});
    }
  s.force = n.get_positive("force", s.force);
  s.axial_force = n.get_positive("axial_force", s.axial_force);
  s.moment = n.get_positive("moment", s.moment);
  s.torque = n.get_positive("torque", s.torque);
  s.self_weight_time = n.get_positive("self_weight_time", s.self_weight_time);
  s.torque_time = n.get_positive("torque_time", s.torque_time);
  s.angle_time = n.get_positive("angle_time", s.angle_time);
  s.time_step = n.get_positive("time_step", s.time_step);
  s.window = n.get_positive("window", s.window);
  s.modes = n.get_int("modes", s.modes);
  s.gravity = n.get_positive("gravity", s.gravity);
  s.angle_amplitude = n.get_positive("angle_amplitude", s.angle_amplitude);
  return s;
}

std::string vec_text(const Vec3& v) {
  std::ostringstream o;
  o.precision(12);
  o << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return o.str();
}

// The parts of a model that the tests vary: support, loads, drives, gravity, solver.
struct Scenario {
  std::string support = "clamp";  // clamp, hinge, hinge_driven, free
  std::vector<std::string> loads;  // YAML flow maps
  bool gravity = false;
  bool statics = true, dynamics = false;
  double t_end = 0.0, rho_infinity = 1.0;
};

std::map<std::string, std::string> substitutions(const Settings& st, const Scenario& sc, Variant v) {
  std::map<std::string, std::string> out;
  out["lattice_type"] = v == Variant::full ? "lattice" : "super_truss";
  out["gravity"] = sc.gravity ? "gravity: [0, 0, -" + CsvTable::number(st.gravity) + "]" : "";
  // psi = -A (1 - cos(pi t / 5)) = A sin(pi t / 5 + pi / 2) - A.
  out["drives"] = sc.support == "hinge_driven"
                      ? "drives:\n  swing: {type: sine, amplitude: " + CsvTable::number(st.angle_amplitude) +
                            ", frequency: 0.1, phase: 1.5707963267948966, offset: " + CsvTable::number(-st.angle_amplitude) + "}"
                      : "";
  std::string c = "constraints:\n";
  for (const auto& sp : st.splices)
    c += "  - {name: splice_" + sp[0] + ", type: fixed, joints: [" + sp[0] + ", " + sp[1] + "], shared: true}\n";
  if (sc.support == "clamp") c += "  - {name: support, type: fixed, joints: [ground.root, " + st.root + "]}\n";
  if (sc.support == "hinge") c += "  - {name: support, type: revolute, axis: y, joints: [ground.root, " + st.root + "]}\n";
  if (sc.support == "hinge_driven")
    c += "  - {name: support, type: revolute, axis: y, joints: [ground.root, " + st.root + "], drive: swing}\n";
  out["constraints"] = c == "constraints:\n" ? "" : c;
  std::string l;
  for (const auto& load : sc.loads) l += "  - " + load + "\n";
  out["loads"] = l.empty() ? "" : "loads:\n" + l;
  char solver[256];
  if (sc.dynamics)
    std::snprintf(solver, sizeof solver,
                  "solver:\n  static: {enabled: %s}\n  dynamics: {t_end: %.10g, time_step: %.10g, rho_infinity: %.3g}",
                  sc.statics ? "true" : "false", sc.t_end, st.time_step, sc.rho_infinity);
  else
    std::snprintf(solver, sizeof solver, "solver:\n  static: {load_steps: 1}");
  out["solver"] = solver;
  out["output"] = "output: {interval: " + CsvTable::number(sc.dynamics ? st.time_step : 0.0) + ", probes: [" + st.tip + "]}";
  return out;
}

// Tip displacement and rotation vector (inertial frame) at the end of a run.
struct TipResponse {
  Vec3 u = Vec3::Zero(), theta = Vec3::Zero();
};

TipResponse tip_response(const Trajectory& tr, const std::string& tip) {
  const int j = tr.simulation->model.find_joint(tip);
  TipResponse r;
  r.u = tr.joints.back()[j] - tr.joints0[j];
  r.theta = rotation_vector(tr.frames.back()[j]);
  return r;
}

double component(const TipResponse& r, int k) { return k < 3 ? r.u(k) : r.theta(k - 3); }

// Lattice node velocities of a state (full model: the node blocks; reduced: the super truss
// elements' map), body by body in the geometry's node order.
std::vector<double> lattice_node_motion(const ModelState& state, const Settings& st) {
  const Model& m = state.model();
  std::vector<double> out;
  for (const std::string& body_name : st.bodies) {
    const int b = m.find_body(body_name);
    const Body& body = m.bodies[b];
    if (body.type == "super_truss") {
      const int e = body.elements.front();
      const auto* element = dynamic_cast<const SuperTrussElement*>(m.elements[e].element.get());
      for (const Vec3& v : element->node_velocities(state.element_slots(e))) out.insert(out.end(), v.data(), v.data() + 3);
    } else {
      for (int k = 1;; ++k) {
        const std::string label = body_name + ".node" + std::to_string(k);
        int found = -1;
        for (std::size_t blk = 0; blk < m.blocks.size() && found < 0; ++blk)
          if (m.blocks[blk].label == label && m.blocks[blk].kind == SlotKind::translation) found = static_cast<int>(blk);
        if (found < 0) break;
        const Vec3& v = state.block(found).vel;
        out.insert(out.end(), v.data(), v.data() + 3);
      }
    }
  }
  return out;
}

double mac(const std::vector<double>& a, const std::vector<double>& b) {
  double ab = 0, aa = 0, bb = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    ab += a[i] * b[i];
    aa += a[i] * a[i];
    bb += b[i] * b[i];
  }
  return aa > 0 && bb > 0 ? ab * ab / (aa * bb) : 0.0;
}

struct ModalResult {
  std::vector<double> frequency;
  std::vector<std::vector<double>> shape;
  int dofs = 0, multipliers = 0;
  double nonzeros = 0;
};

// Statics under self-weight, then the lowest modes about that state.
ModalResult modal_run(const std::string& path, const Settings& st) {
  ModalResult out;
  Simulation sim = read_simulation(path);
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&U));
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&V));
  PetscCallAbort(PETSC_COMM_SELF, sa.initial_state(U, V));
  SimulationOutcome outcome;
  std::vector<Mode> modes;
  std::string message;
  PetscCallAbort(PETSC_COMM_SELF, equilibrium_modes(sim, sa, U, V, st.modes, &modes, &outcome, &message));
  if (!outcome.ok()) throw std::runtime_error("statics before the modal analysis failed: " + outcome.statics.message);
  ModelState state(sim.model, sa.dofs());
  for (const Mode& mode : modes) {
    PetscCallAbort(PETSC_COMM_SELF, sa.gather(0.0, U, mode.vector, nullptr, Parametrization::velocity_variables, &state));
    out.frequency.push_back(mode.frequency);
    out.shape.push_back(lattice_node_motion(state, st));
  }
  destroy_modes(modes);
  out.dofs = sim.model.num_free_dofs();
  out.multipliers = sim.model.num_multipliers();
  Mat J;
  PetscCallAbort(PETSC_COMM_SELF, sa.create_matrix(&J));
  EvaluationSettings how;
  PetscCallAbort(PETSC_COMM_SELF, sa.jacobian(EvaluationPoint{U, V, nullptr, nullptr, 0, 0}, how, 1, 0, 0, J));
  MatInfo info;
  PetscCallAbort(PETSC_COMM_SELF, MatGetInfo(J, MAT_GLOBAL_SUM, &info));
  out.nonzeros = info.nz_used;
  MatDestroy(&J);
  VecDestroy(&U);
  VecDestroy(&V);
  return out;
}

// Members of the first body near its end 1: the main-beam segments of the first bay and the
// sub-beams of the first two bays, with their axial forces in both models.
struct MemberForces {
  std::vector<std::string> label;
  std::vector<double> full, reduced;
};

std::vector<double> body_member_forces(const Trajectory& tr, const std::string& body_name) {
  const Model& m = tr.simulation->model;
  const Body& body = m.bodies[m.find_body(body_name)];
  std::vector<double> out;
  if (body.type == "super_truss") {
    const int e = body.elements.front();
    const auto* element = dynamic_cast<const SuperTrussElement*>(m.elements[e].element.get());
    return element->member_axial_forces(tr.final_state->element_slots(e));
  }
  for (int e : body.elements) out.push_back(tr.final_state->axial_force(e).value_or(NAN));
  return out;
}

// Each member's largest von Mises stress over a run (the recorder's peaks), for the body's
// elements in order: the full lattice's member by member, the super truss's as recovered from its
// coordinates.
std::vector<double> body_member_peaks(const Trajectory& tr, const std::string& body_name) {
  const Model& m = tr.simulation->model;
  std::vector<double> out;
  for (int e : m.bodies[m.find_body(body_name)].elements) {
    const auto& p = tr.member_peaks.at(static_cast<std::size_t>(e));
    out.insert(out.end(), p.begin(), p.end());
  }
  return out;
}

// Twice the kinetic energy of unit rigid motions of the whole model (translations along x, y, z;
// rotations about axes through the centre of the blocks' bounding box), from the elements'
// energies with the blocks' velocities set to the rigid field.
std::array<double, 6> rigid_motion_masses(const std::string& path) {
  Simulation sim = read_simulation(path);
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&U));
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&V));
  PetscCallAbort(PETSC_COMM_SELF, sa.initial_state(U, V));
  ModelState state(sim.model, sa.dofs());
  PetscCallAbort(PETSC_COMM_SELF, sa.gather(0.0, U, V, nullptr, Parametrization::velocity_variables, &state));
  const Model& m = sim.model;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t b = 0; b < m.blocks.size(); ++b)
    if (m.blocks[b].kind == SlotKind::translation) {
      lo = lo.cwiseMin(state.block(static_cast<int>(b)).pos);
      hi = hi.cwiseMax(state.block(static_cast<int>(b)).pos);
    }
  const Vec3 centre = 0.5 * (lo + hi);
  const PetscScalar* u;
  PetscInt n;
  PetscCallAbort(PETSC_COMM_SELF, VecGetSize(U, &n));
  PetscCallAbort(PETSC_COMM_SELF, VecGetArrayRead(U, &u));
  const std::vector<double> uu(u, u + n);
  PetscCallAbort(PETSC_COMM_SELF, VecRestoreArrayRead(U, &u));
  std::array<double, 6> out{};
  for (int d = 0; d < 6; ++d) {
    std::vector<double> v(static_cast<std::size_t>(n), 0.0);
    const Vec3 e = Vec3::Unit(d % 3);
    for (std::size_t b = 0; b < m.blocks.size(); ++b) {
      const DofBlock& blk = m.blocks[b];
      if (blk.fixed) continue;
      const int at = sa.dofs().block_dof(static_cast<int>(b));
      const BlockState& bs = state.block(static_cast<int>(b));
      Vec3 w = Vec3::Zero();
      if (blk.kind == SlotKind::translation) w = d < 3 ? e : Vec3(e.cross(bs.pos - centre));
      if (blk.kind == SlotKind::rotation && d >= 3) w = bs.rot.transpose() * e;  // body angular velocity
      if (blk.kind == SlotKind::translation || blk.kind == SlotKind::rotation)
        for (int i = 0; i < 3; ++i) v[static_cast<std::size_t>(at + i)] = w(i);
    }
    state.set(0.0, uu, v, {}, Parametrization::velocity_variables);
    out[static_cast<std::size_t>(d)] = 2 * state.energy().kinetic;
  }
  VecDestroy(&U);
  VecDestroy(&V);
  return out;
}

}  // namespace

std::vector<Verdict> run_lattice_reduction_study(const Study& s) {
  const Settings st = read_settings(s.root()["settings"]);
  for (const InputNode& a : s.root()["acceptance"].items()) a.allow_only({"quantity", "min", "max", "why"});  // fail early
  const std::filesystem::path dir = s.out_dir();
  std::map<std::string, double> value;  // measured quantity -> reduced / full (or MAC)

  // 1. Statics: tip response to each load (8.2.3, equivalent stiffness).
  struct Load {
    const char* name;
    int primary;  // 0..2 displacement, 3..5 rotation
    std::string yaml;
  };
  const std::string tip = st.tip;
  auto force = [&](const Vec3& f) { return "{name: tip, joint: " + tip + ", force: " + vec_text(f) + "}"; };
  auto moment = [&](const Vec3& m) { return "{name: tip, joint: " + tip + ", moment: " + vec_text(m) + "}"; };
  const std::vector<Load> loads = {{"self_weight", 2, ""},
                                   {"force_x", 0, force(Vec3(st.axial_force, 0, 0))},
                                   {"force_y", 1, force(Vec3(0, st.force, 0))},
                                   {"force_z", 2, force(Vec3(0, 0, st.force))},
                                   {"moment_x", 3, moment(Vec3(st.moment, 0, 0))},
                                   {"moment_y", 4, moment(Vec3(0, st.moment, 0))},
                                   {"moment_z", 5, moment(Vec3(0, 0, st.moment))}};
  CsvTable statics(dir / "statics.csv", {"load", "model", "ux", "uy", "uz", "theta_x", "theta_y", "theta_z"});
  std::ofstream md(dir / "lattice.md");
  md << "### Static tip response (cantilever)\n\n| load | full | reduced | reduced / full |\n|---|---|---|---|\n";
  const char* comp_name[6] = {"u_x", "u_y", "u_z", "theta_x", "theta_y", "theta_z"};
  for (const Load& load : loads) {
    Scenario sc;
    sc.gravity = std::string(load.name) == "self_weight";
    if (!load.yaml.empty()) sc.loads = {load.yaml};
    TipResponse r[2];
    for (Variant v : {Variant::full, Variant::reduced}) {
      SimulationOutcome outcome;
      const Trajectory tr = s.run(std::string("static_") + load.name + "_" + name_of(v), substitutions(st, sc, v), &outcome);
      if (!outcome.ok()) throw std::runtime_error(std::string("static ") + load.name + " " + name_of(v) + ": " + outcome.statics.message);
      r[v == Variant::full ? 0 : 1] = tip_response(tr, tip);
      const TipResponse& x = r[v == Variant::full ? 0 : 1];
      statics.row({load.name, name_of(v), CsvTable::number(x.u.x()), CsvTable::number(x.u.y()), CsvTable::number(x.u.z()),
                   CsvTable::number(x.theta.x()), CsvTable::number(x.theta.y()), CsvTable::number(x.theta.z())});
    }
    const double f = component(r[0], load.primary), red = component(r[1], load.primary);
    value[std::string("static.") + load.name] = red / f;
    char line[256];
    std::snprintf(line, sizeof line, "| %s (%s) | %.5g | %.5g | %.4f |\n", load.name, comp_name[load.primary], f, red, red / f);
    md << line;
    std::printf("static %-12s %-8s full %.6g reduced %.6g ratio %.4f\n", load.name, comp_name[load.primary], f, red, red / f);
  }

  // 2. Equivalent mass (8.2.3): twice the kinetic energy of a rigid motion of unit speed,
  // translations along x, y, z and rotations about axes through the middle of the truss axis.
  md << "\n### Equivalent mass (kinetic energy of rigid motions: 2 T / v^2)\n\n| motion | full | reduced | reduced / full |\n|---|---|---|---|\n";
  CsvTable mass(dir / "mass.csv", {"motion", "full", "reduced", "ratio"});
  Scenario free_sc;
  free_sc.support = "free";
  double eq[2][6];
  for (Variant v : {Variant::full, Variant::reduced}) {
    const std::array<double, 6> m = rigid_motion_masses(s.instantiate(std::string("mass_") + name_of(v), substitutions(st, free_sc, v)));
    for (int d = 0; d < 6; ++d) eq[v == Variant::full ? 0 : 1][d] = m[d];
  }
  const char* motion[6] = {"translation x", "translation y", "translation z", "rotation about x", "rotation about y",
                           "rotation about z"};
  for (int d = 0; d < 6; ++d) {
    value[std::string("mass.") + "xyz"[d % 3] + (d < 3 ? "" : "_rot")] = eq[1][d] / eq[0][d];
    mass.row({motion[d], CsvTable::number(eq[0][d]), CsvTable::number(eq[1][d]), CsvTable::number(eq[1][d] / eq[0][d])});
    char line[200];
    std::snprintf(line, sizeof line, "| %s | %.6g %s | %.6g | %.5f |\n", motion[d], eq[0][d], d < 3 ? "kg" : "kg m^2", eq[1][d],
                  eq[1][d] / eq[0][d]);
    md << line;
    std::printf("mass %-17s full %.6g reduced %.6g ratio %.5f\n", motion[d], eq[0][d], eq[1][d], eq[1][d] / eq[0][d]);
  }

  // 3. Natural frequencies about the static state under self-weight, modes paired by MAC.
  Scenario modal_sc;
  modal_sc.gravity = true;
  ModalResult modal[2];
  for (Variant v : {Variant::full, Variant::reduced})
    modal[v == Variant::full ? 0 : 1] = modal_run(s.instantiate(std::string("modes_") + name_of(v), substitutions(st, modal_sc, v)), st);
  md << "\n### Natural frequencies (cantilever, about the static state), paired by MAC on the lattice nodes' motion\n\n"
     << "| mode (full) | full (Hz) | reduced mode | reduced (Hz) | reduced / full | MAC |\n|---|---|---|---|---|---|\n";
  CsvTable modes(dir / "modes.csv", {"mode", "full_hz", "reduced_mode", "reduced_hz", "ratio", "mac"});
  for (std::size_t i = 0; i < modal[0].frequency.size(); ++i) {
    std::size_t best = 0;
    double best_mac = -1;
    for (std::size_t k = 0; k < modal[1].frequency.size(); ++k) {
      const double m = mac(modal[0].shape[i], modal[1].shape[k]);
      if (m > best_mac) best_mac = m, best = k;
    }
    const double ff = modal[0].frequency[i], fr = modal[1].frequency[best];
    value["frequency." + std::to_string(i + 1)] = fr / ff;
    value["mac." + std::to_string(i + 1)] = best_mac;
    modes.row({std::to_string(i + 1), CsvTable::number(ff), std::to_string(best + 1), CsvTable::number(fr),
               CsvTable::number(fr / ff), CsvTable::number(best_mac)});
    char line[200];
    std::snprintf(line, sizeof line, "| %zu | %.4f | %zu | %.4f | %.4f | %.3f |\n", i + 1, ff, best + 1, fr, fr / ff, best_mac);
    md << line;
    std::printf("mode %zu full %.5f Hz, reduced mode %zu %.5f Hz (ratio %.4f), MAC %.3f\n", i + 1, ff, best + 1, fr, fr / ff, best_mac);
  }

  // Each member's largest von Mises stress per run, full [0] and reduced [1] (sections 4, 5, 6).
  std::map<std::string, std::array<std::vector<double>, 2>> stress_peaks;

  // 4. Dynamics: self-weight release (8.2.1), end torque and angle drive about a hinge (8.2.2).
  CsvTable series(dir / "dynamics_series.csv", {"test", "model", "time", "tip_deflection"});
  md << "\n### Dynamic tip response\n\n| test | quantity | full | reduced | reduced / full |\n|---|---|---|---|---|\n";
  double wall_per_step[2] = {0, 0};
  struct DynamicTest {
    const char* name;
    Scenario sc;
  };
  std::vector<DynamicTest> dyn(3);
  dyn[0].name = "self_weight";
  dyn[0].sc.gravity = true;
  dyn[0].sc.statics = false;
  dyn[0].sc.dynamics = true;
  dyn[0].sc.t_end = st.self_weight_time;
  dyn[1].name = "torque";
  dyn[1].sc.support = "hinge";
  dyn[1].sc.statics = false;
  dyn[1].sc.dynamics = true;
  dyn[1].sc.t_end = st.torque_time;
  dyn[1].sc.rho_infinity = 0.9;
  dyn[1].sc.loads = {"{name: torque, joint: " + tip + ", moment: " + vec_text(Vec3(0, st.torque, 0)) + "}"};
  dyn[2].name = "angle";
  dyn[2].sc.support = "hinge_driven";
  dyn[2].sc.statics = false;
  dyn[2].sc.dynamics = true;
  dyn[2].sc.t_end = st.angle_time;
  dyn[2].sc.rho_infinity = 0.9;
  for (const DynamicTest& test : dyn) {
    std::vector<double> t[2], w[2];
    for (Variant v : {Variant::full, Variant::reduced}) {
      const int i = v == Variant::full ? 0 : 1;
      SimulationOutcome outcome;
      const Trajectory tr = s.run(std::string("dynamic_") + test.name + "_" + name_of(v), substitutions(st, test.sc, v), &outcome);
      stress_peaks[test.name][i] = body_member_peaks(tr, st.bodies.front());
      if (!outcome.ok()) std::printf("dynamic %s %s FAILED: %s\n", test.name, name_of(v), outcome.dynamics.message.c_str());
      const Model& m = tr.simulation->model;
      const int jt = m.find_joint(tip), jr = m.find_joint(st.root);
      for (std::size_t k = 0; k < tr.time.size(); ++k) {
        // Self-weight: the tip's vertical displacement; rotations: the tip across the root frame.
        const double d = std::string(test.name) == "self_weight"
                             ? tr.joints[k][jt].z() - tr.joints0[jt].z()
                             : (tr.frames[k][jr].transpose() * (tr.joints[k][jt] - tr.joints[k][jr])).z();
        t[i].push_back(tr.time[k]);
        w[i].push_back(d);
        series.row({test.name, name_of(v), CsvTable::number(tr.time[k]), CsvTable::number(d)});
      }
      if (std::string(test.name) == "self_weight" && outcome.dynamics.steps > 0)
        wall_per_step[i] = outcome.dynamics.wall_seconds / static_cast<double>(outcome.dynamics.steps);
    }
    auto swing = [](const std::vector<double>& x) {
      return *std::max_element(x.begin(), x.end()) - *std::min_element(x.begin(), x.end());
    };
    const std::vector<double> mf = moving_average(t[0], w[0], st.window), mr = moving_average(t[1], w[1], st.window);
    const double ff = oscillation_frequency(t[0], w[0], mf), fr = oscillation_frequency(t[1], w[1], mr);
    double mean_f = 0, mean_r = 0;
    int count = 0;
    for (std::size_t k = 0; k < std::min(mf.size(), mr.size()); ++k)
      if (std::isfinite(mf[k]) && std::isfinite(mr[k])) mean_f += mf[k], mean_r += mr[k], ++count;
    const double sf = swing(w[0]), sr = swing(w[1]);
    value[std::string("dynamic.") + test.name + "_swing"] = sr / sf;
    value[std::string("dynamic.") + test.name + "_frequency"] = fr / ff;
    if (count > 0) value[std::string("dynamic.") + test.name + "_mean"] = mean_r / mean_f;
    char line[300];
    std::snprintf(line, sizeof line, "| %s | swing (m) | %.5g | %.5g | %.4f |\n| %s | vibration frequency (Hz) | %.4f | %.4f | %.4f |\n",
                  test.name, sf, sr, sr / sf, test.name, ff, fr, fr / ff);
    md << line;
    if (count > 0) {
      std::snprintf(line, sizeof line, "| %s | mean deflection (m) | %.5g | %.5g | %.4f |\n", test.name, mean_f / count,
                    mean_r / count, mean_r / mean_f);
      md << line;
    }
    std::printf("dynamic %-11s swing %.5g / %.5g (%.4f), frequency %.4f / %.4f Hz (%.4f)\n", test.name, sf, sr, sr / sf, ff, fr,
                fr / ff);
  }

  // 5. Member forces near the root under self-weight and a tip force along z.
  Scenario member_sc;
  member_sc.gravity = true;
  member_sc.loads = {force(Vec3(0, 0, -st.force))};
  std::vector<double> forces[2];
  const TrussGeometry* geometry = nullptr;
  Trajectory reduced_tr;
  for (Variant v : {Variant::full, Variant::reduced}) {
    SimulationOutcome outcome;
    Trajectory tr = s.run(std::string("members_") + name_of(v), substitutions(st, member_sc, v), &outcome);
    forces[v == Variant::full ? 0 : 1] = body_member_forces(tr, st.bodies.front());
    stress_peaks["static"][v == Variant::full ? 0 : 1] = body_member_peaks(tr, st.bodies.front());
    if (v == Variant::reduced) reduced_tr = std::move(tr);
  }
  {
    const Model& m = reduced_tr.simulation->model;
    const Body& body = m.bodies[m.find_body(st.bodies.front())];
    geometry = &dynamic_cast<const SuperTrussElement*>(m.elements[body.elements.front()].element.get())->geometry();
  }
  auto station = [&](int n) {
    const TrussNode& node = geometry->nodes[n];
    return node.kind == TrussNode::Kind::end1 ? 0 : node.kind == TrussNode::Kind::end2 ? 1000 : node.station;
  };
  md << "\n### Member axial forces near the root (self-weight and a tip force " << CsvTable::number(-st.force)
     << " N along z)\n\n| member | nodes | full (N) | reduced (N) | reduced / full |\n|---|---|---|---|---|\n";
  CsvTable members(dir / "members.csv", {"member", "kind", "node_a", "node_b", "full", "reduced"});
  double worst_chord = 1.0, worst_diag = 1.0;
  double max_diag_full = 0.0;
  for (std::size_t i = 0; i < geometry->members.size(); ++i) {
    const TrussMember& mem = geometry->members[i];
    if (mem.kind == TrussMemberKind::sub) max_diag_full = std::max(max_diag_full, std::abs(forces[0][i]));
  }
  for (std::size_t i = 0; i < geometry->members.size(); ++i) {
    const TrussMember& mem = geometry->members[i];
    const bool root_chord = mem.kind == TrussMemberKind::main && std::min(station(mem.a), station(mem.b)) == 0;
    const bool root_diag = mem.kind == TrussMemberKind::sub && std::max(station(mem.a), station(mem.b)) <= 2;
    if (!root_chord && !root_diag) continue;
    const double ratio = forces[1][i] / forces[0][i];
    if (root_chord) worst_chord = std::abs(ratio - 1) > std::abs(worst_chord - 1) ? ratio : worst_chord;
    // Diagonals: compare against the most loaded one (small forces make ratios meaningless).
    if (root_diag && std::abs(forces[0][i]) > 0.25 * max_diag_full)
      worst_diag = std::abs(ratio - 1) > std::abs(worst_diag - 1) ? ratio : worst_diag;
    const std::string label = std::string(root_chord ? "chord " : "diagonal ") + std::to_string(i + 1);
    members.row({std::to_string(i + 1), to_string(mem.kind), std::to_string(mem.a + 1), std::to_string(mem.b + 1),
                 CsvTable::number(forces[0][i]), CsvTable::number(forces[1][i])});
    char line[200];
    std::snprintf(line, sizeof line, "| %s | %d-%d | %.5g | %.5g | %.4f |\n", label.c_str(), mem.a + 1, mem.b + 1, forces[0][i],
                  forces[1][i], ratio);
    md << line;
  }
  value["member.root_chord"] = worst_chord;
  value["member.root_diagonal"] = worst_diag;
  std::printf("members: worst root chord ratio %.4f, worst loaded root diagonal ratio %.4f\n", worst_chord, worst_diag);

  // 6. Member stresses: every member's largest von Mises stress in the full model against the one
  // recovered from the super truss's coordinates, per run. Ratios of the most stressed members
  // (within half the body's largest stress) by kind, and the most stressed member of each model.
  md << "\n### Member stresses, full against recovered from the super truss\n\n"
        "Each member's largest von Mises stress over the run (statics: at the equilibrium of the member forces above); "
        "ratios over the members stressed to at least half the full model's largest.\n\n"
        "| run | largest full (MPa), member | largest reduced (MPa), member | largest: reduced / full | chords: median, worst | "
        "lacing: median, worst |\n|---|---|---|---|---|---|\n";
  CsvTable stress_csv(dir / "member_stresses.csv", {"run", "member", "kind", "node_a", "node_b", "full_pa", "reduced_pa"});
  for (const auto& [run, peaks] : stress_peaks) {
    const std::vector<double>& full = peaks[0];
    const std::vector<double>& red = peaks[1];
    if (full.size() != geometry->members.size() || red.size() != geometry->members.size()) {
      std::printf("stresses %s: %zu full and %zu reduced members for %zu in the geometry; skipped\n", run.c_str(), full.size(),
                  red.size(), geometry->members.size());
      continue;
    }
    const auto top_full = std::max_element(full.begin(), full.end()) - full.begin();
    const auto top_red = std::max_element(red.begin(), red.end()) - red.begin();
    std::vector<double> ratios[2];  // main (chords), sub and cross (lacing)
    for (std::size_t i = 0; i < full.size(); ++i) {
      const TrussMember& mem = geometry->members[i];
      stress_csv.row({run, std::to_string(i + 1), to_string(mem.kind), std::to_string(mem.a + 1), std::to_string(mem.b + 1),
                      CsvTable::number(full[i]), CsvTable::number(red[i])});
      if (full[i] >= 0.5 * full[static_cast<std::size_t>(top_full)])
        ratios[mem.kind == TrussMemberKind::main ? 0 : 1].push_back(red[i] / full[i]);
    }
    auto median = [](std::vector<double> x) -> double {
      if (x.empty()) return NAN;
      std::nth_element(x.begin(), x.begin() + static_cast<long>(x.size() / 2), x.end());
      return x[x.size() / 2];
    };
    auto worst = [](const std::vector<double>& x) -> double {
      double w = NAN;
      for (double r : x) w = (std::isnan(w) || std::abs(std::log(r)) > std::abs(std::log(w))) ? r : w;
      return w;
    };
    auto label = [&](std::ptrdiff_t i) {
      const TrussMember& mem = geometry->members[static_cast<std::size_t>(i)];
      return std::string(to_string(mem.kind)) + " " + std::to_string(i + 1) + " (" + std::to_string(mem.a + 1) + "-" +
             std::to_string(mem.b + 1) + ")";
    };
    const double largest = red[static_cast<std::size_t>(top_red)] / full[static_cast<std::size_t>(top_full)];
    value["stress." + run + "_largest"] = largest;
    value["stress." + run + "_chords"] = median(ratios[0]);
    if (!ratios[1].empty()) value["stress." + run + "_lacing"] = median(ratios[1]);
    char line[400];
    std::snprintf(line, sizeof line, "| %s | %.4g, %s | %.4g, %s | %.4f | %.3f, %.3f | %.3f, %.3f |\n", run.c_str(),
                  1e-6 * full[static_cast<std::size_t>(top_full)], label(top_full).c_str(),
                  1e-6 * red[static_cast<std::size_t>(top_red)], label(top_red).c_str(), largest, median(ratios[0]),
                  worst(ratios[0]), median(ratios[1]), worst(ratios[1]));
    md << line;
    std::printf("stresses %-11s largest full %.4g MPa (%s), reduced %.4g MPa (%s): %.4f; chords median %.3f, lacing median %.3f\n",
                run.c_str(), 1e-6 * full[static_cast<std::size_t>(top_full)], label(top_full).c_str(),
                1e-6 * red[static_cast<std::size_t>(top_red)], label(top_red).c_str(), largest, median(ratios[0]),
                median(ratios[1]));
  }

  // 7. Cost.
  md << "\n### Size and cost\n\n| model | DoFs | multipliers | Jacobian nonzeros | wall time per step (self-weight run) |\n|---|---|---|---|---|\n";
  CsvTable cost(dir / "cost.csv", {"model", "dofs", "multipliers", "nonzeros", "seconds_per_step"});
  for (int i = 0; i < 2; ++i) {
    cost.row({i == 0 ? "full" : "reduced", std::to_string(modal[i].dofs), std::to_string(modal[i].multipliers),
              CsvTable::number(modal[i].nonzeros), CsvTable::number(wall_per_step[i])});
    char line[200];
    std::snprintf(line, sizeof line, "| %s | %d | %d | %.0f | %.3g ms |\n", i == 0 ? "full" : "reduced", modal[i].dofs,
                  modal[i].multipliers, modal[i].nonzeros, 1e3 * wall_per_step[i]);
    md << line;
  }

  // Acceptance: each entry bounds one measured ratio (or MAC).
  std::vector<Verdict> verdicts;
  CsvTable summary(dir / "summary.csv", {"quantity", "value"});
  for (const auto& [k, v] : value) summary.row({k, CsvTable::number(v)});
  for (const InputNode& a : s.root()["acceptance"].items()) {
    a.allow_only({"quantity", "min", "max", "why"});
    const std::string q = a["quantity"].as_string();
    const auto it = value.find(q);
    if (it == value.end()) a["quantity"].fail("the study measures no '" + q + "' (see summary.csv for the names)");
    const double lo = a.has("min") ? a["min"].as_double() : -INFINITY, hi = a.has("max") ? a["max"].as_double() : INFINITY;
    char what[200];
    std::snprintf(what, sizeof what, "%s = %.4f (within [%g, %g])", q.c_str(), it->second, lo, hi);
    verdicts.push_back({what, std::isfinite(it->second) && it->second >= lo && it->second <= hi});
  }
  return verdicts;
}

}  // namespace latticedyn
