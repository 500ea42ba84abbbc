// The compiled part of the Python module `camdyn` (docs/python.md): the
// public C++ API (<camdyn/camdyn.h>) and the study dispatch the CLI runs
// (cli/run_study.h), in Python types. camdyn/__init__.py wraps it in the
// classes and functions users call; names here start with `_` unless they
// are the module's own (the exceptions, the version).
//
// The GIL is released around everything that computes (loading a scene
// builds its cam, simulating, running a study), so a thread pool simulates
// in parallel; a simulation on the main thread still stops on Ctrl-C
// (signal_check). C++ exceptions become camdyn.InputError (a bad input: the
// file, the dotted path and the reason as attributes) and camdyn.SolverError
// (a solver gave up); nothing camdyn throws on purpose arrives as a bare
// RuntimeError.
#include <Python.h>
#include <camdyn/camdyn.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <exception>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cli/run_study.h"

namespace py = pybind11;

namespace {

// The exception types, created once at import and kept for the process's
// life (never released: a translator may run until the interpreter ends).
PyObject* error_type = nullptr;
PyObject* input_error_type = nullptr;
PyObject* solver_error_type = nullptr;

PyObject* new_exception(const char* name, const char* doc, PyObject* bases) {
  PyObject* type = PyErr_NewExceptionWithDoc(name, doc, bases, nullptr);
  if (type == nullptr) throw py::error_already_set();
  return type;
}

void add_exceptions(py::module_& m) {
  error_type = new_exception("camdyn.Error", "Base class of the errors camdyn raises.", PyExc_Exception);
  const py::tuple input_bases = py::make_tuple(py::handle(error_type), py::handle(PyExc_ValueError));
  input_error_type = new_exception("camdyn.InputError",
                                   "Invalid input: a config, a data file or a cam that cannot be made (the CLI's "
                                   "exit code 2). Attributes: file (may be empty), path (the dotted config path, "
                                   "or 'line N' of a CSV file) and reason.",
                                   input_bases.ptr());
  const py::tuple solver_bases = py::make_tuple(py::handle(error_type), py::handle(PyExc_RuntimeError));
  solver_error_type = new_exception("camdyn.SolverError",
                                    "A solver gave up (the CLI's exit code 3). Attributes: termination (how a "
                                    "simulation ended, or None) and result (the partial result, or None).",
                                    solver_bases.ptr());
  m.attr("Error") = py::handle(error_type);
  m.attr("InputError") = py::handle(input_error_type);
  m.attr("SolverError") = py::handle(solver_error_type);
}

// Raises `type(message)` with the given attributes set on the instance.
void raise_with(PyObject* type, const char* message, std::initializer_list<std::pair<const char*, py::object>> attrs) {
  py::object instance = py::reinterpret_borrow<py::object>(type)(message);
  for (const auto& [name, value] : attrs) instance.attr(name) = value;
  PyErr_SetObject(type, instance.ptr());
}

// By value: the signature pybind11's register_exception_translator takes.
void translate(std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
  try {
    if (p) std::rethrow_exception(p);
  } catch (const camdyn::InputError& e) {
    raise_with(input_error_type, e.what(),
               {{"file", py::str(e.file())}, {"path", py::str(e.path())}, {"reason", py::str(e.reason())}});
  } catch (const camdyn::NumericalError& e) {
    raise_with(solver_error_type, e.what(), {{"termination", py::none()}, {"result", py::none()}});
  }
}

py::array_t<double> to_array(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

py::dict to_arrays(const camdyn::Columns& columns) {
  py::dict d;
  for (std::size_t i = 0; i < columns.names.size(); ++i) d[py::str(columns.names[i])] = to_array(columns.values[i]);
  return d;
}

// The columns of Result::events (time [s], cam_angle_deg [deg], onset, speed [m/s], impact, grazing, lash).
py::dict events_dict(const std::vector<camdyn::Event>& events) {
  const auto n = static_cast<py::ssize_t>(events.size());
  py::array_t<double> time(n), angle(n), speed(n);
  py::array_t<bool> onset(n), impact(n), grazing(n), lash(n);
  py::list cause;
  for (py::ssize_t i = 0; i < n; ++i) {
    const camdyn::Event& e = events[static_cast<std::size_t>(i)];
    time.mutable_at(i) = e.time;
    angle.mutable_at(i) = e.cam_angle_deg;
    onset.mutable_at(i) = e.onset;
    speed.mutable_at(i) = e.speed;
    impact.mutable_at(i) = e.impact;
    grazing.mutable_at(i) = e.grazing;
    lash.mutable_at(i) = e.lash;
    cause.append(e.cause);
  }
  py::dict d;
  d["time"] = time;
  d["cam_angle_deg"] = angle;
  d["onset"] = onset;
  d["speed"] = speed;
  d["impact"] = impact;
  d["grazing"] = grazing;
  d["lash"] = lash;
  d["cause"] = cause;
  return d;
}

// RunSummary under summary.json's `solver` names, where it has them.
py::dict solver_dict(const camdyn::Result& r) {
  const camdyn::RunSummary& s = r.solver;
  py::dict d;
  d["termination"] = camdyn::termination_name(s.termination);
  d["converged"] = s.converged();
  d["message"] = s.message;
  d["method"] = s.method;
  d["rtol"] = s.rtol;
  d["atol"] = s.atol;
  d["steps"] = s.steps;
  d["rhs_evaluations"] = s.rhs_evaluations;
  d["events"] = s.events;
  d["tracking_resets"] = s.tracking_resets;
  d["run_time_s"] = s.run_time_s;
  d["error_test_failures"] = s.error_test_failures;
  d["nonlinear_iterations"] = s.nonlinear_iterations;
  d["jacobian_evaluations"] = s.jacobian_evaluations;
  d["restarts"] = s.reinitialisations;
  d["tracking_projections"] = s.projections;
  d["simulated_time_s"] = r.end_time;
  d["evaluated_from_s"] = r.evaluated_from;
  py::dict error;
  error["method"] = s.error_estimated ? "richardson" : "energy";
  if (s.error_estimated) {
    error["position"] = s.error_position;
    error["peak_contact_force"] = s.error_peak_contact_force;
  }
  d["error_estimate"] = error;
  return d;
}

py::dict result_dict(const camdyn::Result& r) {
  py::dict d;
  d["metrics"] = r.metrics;
  d["solver"] = solver_dict(r);
  d["timeseries"] = to_arrays(r.series);
  d["timeseries_columns"] = r.series.names;
  d["samples"] = to_arrays(r.samples);
  d["events"] = events_dict(r.events);
  d["metrics_over"] = r.metrics_over;
  d["steady_state"] = r.steady_state;
  return d;
}

// Python's signal handlers (Ctrl-C: KeyboardInterrupt) during a long call:
// on the main thread, the one they run on, the simulation loop polls them at
// most every 0.25 s (camdyn::InterruptCheck) with the GIL
// taken. A handler that raises stops every run as a used-up study budget
// would (a study keeps what finished and can be resumed); the Python error,
// left set on this thread, is raised when the call returns. Other threads
// run without it (their handlers could not run anyway).
std::unique_ptr<camdyn::InterruptCheck> signal_check() {
  const py::object main_thread = py::module_::import("threading").attr("main_thread")();
  if (py::int_(main_thread.attr("ident")).cast<unsigned long>() != PyThread_get_thread_ident()) return nullptr;
  return std::make_unique<camdyn::InterruptCheck>([] {
    const py::gil_scoped_acquire acquire;
    return PyErr_CheckSignals() != 0;
  });
}

py::dict simulate_dict(const camdyn::Scene& scene, bool record_series, std::vector<double> sample_times, int jobs) {
  camdyn::SimulateOptions options;
  options.record_series = record_series;
  options.sample_times = std::move(sample_times);
  options.jobs = jobs;
  camdyn::Result result;
  {
    const std::unique_ptr<camdyn::InterruptCheck> interrupts = signal_check();
    const py::gil_scoped_release release;
    result = camdyn::simulate(scene, options);
  }
  if (PyErr_Occurred() != nullptr) throw py::error_already_set();  // a signal handler raised
  return result_dict(result);
}

py::dict model_dict(const camdyn::Scene& scene) {
  const camdyn::ModelInfo info = scene.model();
  py::dict d;
  d["states"] = info.states;
  d["elements"] = info.elements;
  d["cam"] = info.cam;
  d["follower"] = info.follower;
  d["contact_pair"] = info.contact_pair;
  return d;
}

py::dict profile_dict(const camdyn::Scene& scene, int points) {
  const camdyn::CamProfile p = scene.profile(points);
  py::dict d;
  d["u"] = to_array(p.u);
  d["contour_x"] = to_array(p.contour_x);
  d["contour_y"] = to_array(p.contour_y);
  d["pitch_x"] = to_array(p.pitch_x);
  d["pitch_y"] = to_array(p.pitch_y);
  return d;
}

py::dict law_dict(const camdyn::Scene& scene, const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  const std::vector<double> angles(a.data(), a.data() + a.size());
  const camdyn::LawValues v = scene.law(angles);
  py::dict d;
  d["s"] = to_array(v.s);
  d["ds"] = to_array(v.ds);
  d["d2s"] = to_array(v.d2s);
  d["d3s"] = to_array(v.d3s);
  return d;
}

py::dict run_study_dict(const camdyn::StudyRequest& request) {
  camdyn::StudyOutcome outcome;
  {
    const std::unique_ptr<camdyn::InterruptCheck> interrupts = signal_check();
    const py::gil_scoped_release release;
    outcome = camdyn::run_study(request);
  }
  if (PyErr_Occurred() != nullptr) throw py::error_already_set();  // a signal handler raised
  py::dict d;
  d["exit_code"] = outcome.exit_code;
  d["study"] = outcome.study;
  d["out_dir"] = outcome.out_dir.string();
  d["main_output"] = outcome.main_output.string();
  return d;
}

void add_scene(py::module_& m) {
  using camdyn::Scene;
  py::class_<Scene>(m, "_Scene")
      .def_static(
          "load",
          [](const std::string& file, const std::vector<std::string>& overrides) {
            const py::gil_scoped_release release;
            return Scene::load(file, overrides);
          },
          py::arg("file"), py::arg("overrides"))
      .def_static(
          "from_json",
          [](const std::string& text, const std::string& base_dir, const std::vector<std::string>& overrides) {
            const py::gil_scoped_release release;
            return Scene::from_json(text, base_dir, overrides);
          },
          py::arg("text"), py::arg("base_dir"), py::arg("overrides"))
      .def(
          "set",
          [](Scene& scene, const std::string& path, double value) {
            const py::gil_scoped_release release;
            scene.set(path, value);
          },
          py::arg("path"), py::arg("value"))
      .def(
          "set_text",
          [](Scene& scene, const std::string& path, const std::string& value) {
            const py::gil_scoped_release release;
            scene.set(path, value);
          },
          py::arg("path"), py::arg("value"))
      .def_property_readonly("name", &Scene::name)
      .def_property_readonly("rpm", &Scene::rpm)
      .def("resolved_json", &Scene::resolved_json)
      .def("jump_speed_rpm", &Scene::jump_speed_rpm)
      .def("model", &model_dict)
      .def("profile", &profile_dict, py::arg("points"))
      .def("law", &law_dict, py::arg("angles_deg"))
      .def("simulate", &simulate_dict, py::arg("record_series"), py::arg("sample_times"), py::arg("jobs"));
}

}  // namespace

PYBIND11_MODULE(_camdyn, m) {
  m.doc() = "camdyn's compiled core; use the package `camdyn`, which wraps it.";
  m.attr("__version__") = CAMDYN_VERSION;
  add_exceptions(m);
  py::register_exception_translator(&translate);
  // The caps the package checks its arguments against before they reach C++.
  m.attr("_MAX_POINTS_PER_CALL") = camdyn::kMaxPointsPerCall;
  m.attr("_MAX_JOBS") = camdyn::kMaxJobs;
  add_scene(m);
  // The time series' units, from the one table the C++ outputs read (dynamics/series_columns.h).
  m.def("column_unit", &camdyn::column_unit, py::arg("name"), py::arg("oscillating") = false);
  m.def("series_column_units", &camdyn::series_column_units);
  m.def("train_column_units", &camdyn::train_column_units);
  m.def(
      "run_study",
      [](const std::string& config_file, const std::string& json_text, const std::string& base_dir,
         const std::vector<std::string>& overrides, const std::string& out_dir, int jobs, bool summary) {
        camdyn::StudyRequest request;
        request.summary = summary;
        request.config_file = config_file;
        request.json_text = json_text;
        request.base_dir = base_dir;
        request.overrides = overrides;
        request.out_dir = out_dir;
        request.jobs = jobs;
        return run_study_dict(request);
      },
      py::arg("config_file"), py::arg("json_text"), py::arg("base_dir"), py::arg("overrides"), py::arg("out_dir"),
      py::arg("jobs"), py::arg("summary"));
}
