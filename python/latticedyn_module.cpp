// Python bindings of the facade (api/simulator.hpp): `import latticedyn`, Simulator with NumPy
// arrays for vectors and matrices, InputError and SolverError as Python exceptions.
#include "api/simulator.hpp"

#include "io/input_node.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <memory>

namespace py = pybind11;
using latticedyn::Simulator;
using latticedyn::SimulatorState;

namespace {

// PETSc (and MPI) for the interpreter: set up by the first Simulator or by initialize(options),
// finalised at exit when no simulator is left (one still alive then would free its vectors after
// PETSc is gone).
std::unique_ptr<latticedyn::Runtime> runtime;
long simulators_alive = 0;

void initialize(const std::vector<std::string>& options) {
  if (runtime) return;
  static std::vector<std::string> args;  // PETSc keeps argv
  static std::vector<char*> argv;
  args = {"latticedyn"};
  args.insert(args.end(), options.begin(), options.end());
  argv.clear();
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int argc = static_cast<int>(args.size());
  char** argv_ptr = argv.data();
  runtime = std::make_unique<latticedyn::Runtime>(&argc, &argv_ptr);
}

/// A Simulator that counts itself, so that PETSc is finalised only when none is left.
struct PySimulator {
  Simulator sim;
  explicit PySimulator(Simulator s) : sim(std::move(s)) { ++simulators_alive; }
  ~PySimulator() { --simulators_alive; }
  PySimulator(const PySimulator&) = delete;
  PySimulator& operator=(const PySimulator&) = delete;
};

std::vector<latticedyn::Override> overrides_of(const std::map<std::string, std::string>& overrides) {
  std::vector<latticedyn::Override> o;
  for (const auto& [path, yaml] : overrides) o.push_back({path, yaml});
  return o;
}

py::array_t<double> array(const std::vector<double>& v) { return py::array_t<double>(v.size(), v.data()); }

}  // namespace

PYBIND11_MODULE(latticedyn, m) {
  m.doc() = "latticedyn: flexible multibody dynamics of lattice boom cranes (docs/api.md, docs/python.md)";
  m.attr("__version__") = LATTICEDYN_VERSION;

  static py::exception<latticedyn::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<latticedyn::SolverError> solver_error(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const latticedyn::InputError& e) {
      input_error(e.what());
    } catch (const latticedyn::SolverError& e) {
      solver_error(e.what());
    }
  });

  m.def("initialize", &initialize, py::arg("options") = std::vector<std::string>{},
        "Starts PETSc with these options (e.g. ['-dyn_snes_monitor']); the first Simulator does it "
        "without options otherwise.");
  py::module_::import("atexit").attr("register")(py::cpp_function([] {
    if (simulators_alive == 0) runtime.reset();
  }));

  py::class_<SimulatorState>(m, "State", "A saved state (Simulator.save_state); restore_state takes it back.")
      .def_readonly("time", &SimulatorState::time)
      .def_readonly("steps", &SimulatorState::steps)
      .def_property_readonly("coordinates", [](const SimulatorState& s) { return array(s.coordinates); })
      .def_property_readonly("velocities", [](const SimulatorState& s) { return array(s.velocities); });

  py::class_<PySimulator>(m, "Simulator",
                          "One model and its simulation: statics, dynamics advanced with external drives set "
                          "from Python, outputs, saved states (docs/api.md).")
      .def(py::init([](const std::string& path, const std::map<std::string, std::string>& overrides) {
             initialize({});
             return std::make_unique<PySimulator>(Simulator::load(path, overrides_of(overrides)));
           }),
           py::arg("path"), py::arg("overrides") = std::map<std::string, std::string>{},
           "Reads a model file; overrides: {'dotted.key.path': 'YAML value'} applied first.")
      .def_static(
          "from_string",
          [](const std::string& yaml, const std::string& name, const std::map<std::string, std::string>& overrides) {
            initialize({});
            return std::make_unique<PySimulator>(Simulator::load_string(yaml, name, overrides_of(overrides)));
          },
          py::arg("yaml"), py::arg("name") = "model.yaml", py::arg("overrides") = std::map<std::string, std::string>{})
      .def_property_readonly("time", [](const PySimulator& s) { return s.sim.time(); })
      .def_property_readonly("time_step", [](const PySimulator& s) { return s.sim.time_step(); })
      .def_property_readonly("steps", [](const PySimulator& s) { return s.sim.steps(); })
      .def_property_readonly("title", [](const PySimulator& s) { return s.sim.model().title; })
      .def(
          "solve_statics",
          [](PySimulator& s) {
            const latticedyn::StaticsSummary r = s.sim.solve_statics();
            return py::dict(py::arg("increments") = r.increments, py::arg("newton_iterations") = r.newton_iterations,
                            py::arg("residual") = r.residual, py::arg("max_violation") = r.max_violation,
                            py::arg("message") = r.message, py::arg("wall_seconds") = r.wall_seconds);
          },
          "Static equilibrium at the current time; raises SolverError.")
      .def(
          "advance", [](PySimulator& s, double interval) { s.sim.advance(interval); }, py::arg("interval"),
          "Advances the dynamics by interval seconds; raises SolverError (the state is the last accepted step).")
      .def_property_readonly("drive_names", [](const PySimulator& s) { return s.sim.drive_names(); })
      .def_property_readonly("external_drive_names", [](const PySimulator& s) { return s.sim.external_drive_names(); })
      .def(
          "drive",
          [](const PySimulator& s, const std::string& name) {
            const latticedyn::DriveValue v = s.sim.drive(name);
            return py::make_tuple(v.value, v.rate, v.accel);
          },
          py::arg("name"), "(value, rate, acceleration) of a drive now.")
      .def(
          "set_drive_rate", [](PySimulator& s, const std::string& name, double rate) { s.sim.set_drive_rate(name, rate); },
          py::arg("name"), py::arg("rate"))
      .def(
          "set_drive_acceleration",
          [](PySimulator& s, const std::string& name, double a) { s.sim.set_drive_acceleration(name, a); },
          py::arg("name"), py::arg("acceleration"))
      .def(
          "joint_position", [](const PySimulator& s, const std::string& j) { return s.sim.joint_position(j); },
          py::arg("joint"))
      .def(
          "joint_velocity", [](const PySimulator& s, const std::string& j) { return s.sim.joint_velocity(j); },
          py::arg("joint"))
      .def(
          "joint_orientation", [](const PySimulator& s, const std::string& j) { return s.sim.joint_orientation(j); },
          py::arg("joint"), "3 x 3, the joint frame's axes as columns.")
      .def(
          "axial_forces", [](const PySimulator& s, const std::string& b) { return array(s.sim.axial_forces(b)); },
          py::arg("body"), "Per element of the body, N (a rope's tension).")
      .def(
          "constraint_reaction",
          [](const PySimulator& s, const std::string& c) {
            const latticedyn::ConstraintReaction r = s.sim.constraint_reaction(c);
            return py::dict(py::arg("point") = r.point, py::arg("force") = r.force, py::arg("moment") = r.moment);
          },
          py::arg("constraint"))
      .def("energy",
           [](const PySimulator& s) {
             const latticedyn::ElementEnergy e = s.sim.energy();
             return py::dict(py::arg("kinetic") = e.kinetic, py::arg("gravity_potential") = e.gravity_potential,
                             py::arg("strain") = e.strain, py::arg("fluid") = e.fluid);
           })
      .def("probes", [](const PySimulator& s) { return array(s.sim.probes()); })
      .def("coordinates", [](const PySimulator& s) { return array(s.sim.coordinates()); })
      .def(
          "linearize",
          [](const PySimulator& s, const std::vector<std::string>& inputs) {
            const latticedyn::LinearModel lm = s.sim.linearize(inputs);
            return py::dict(py::arg("A") = lm.A, py::arg("B") = lm.B, py::arg("C") = lm.C, py::arg("D") = lm.D,
                            py::arg("independent") = lm.independent, py::arg("inputs") = lm.inputs,
                            py::arg("outputs") = lm.outputs, py::arg("time") = lm.time);
          },
          py::arg("inputs") = std::vector<std::string>{},
          "The linear model about the current state: a dict of A, B, C, D (numpy), independent (dim z), "
          "inputs (drive names; w = their accelerations), outputs (probe joints' x..vz); x = [z, z', u, u'].")
      .def(
          "write_linear_model",
          [](const PySimulator& s, const std::string& path, const std::vector<std::string>& inputs) {
            Simulator::write_linear_model(path, s.sim.linearize(inputs));
          },
          py::arg("path"), py::arg("inputs") = std::vector<std::string>{}, "linearize(inputs) written as HDF5.")
      .def(
          "natural_frequencies", [](const PySimulator& s, int count) { return s.sim.natural_frequencies(count); },
          py::arg("count") = 6, "The lowest natural frequencies (Hz) about the current (equilibrium) state.")
      .def("save_state", [](const PySimulator& s) { return s.sim.save_state(); })
      .def(
          "restore_state", [](PySimulator& s, const SimulatorState& state) { s.sim.restore_state(state); },
          py::arg("state"));
}
