// rotleak._rotleak: the library in process, for the Python package (python/rotleak/__init__.py wraps
// it). Each function is the library call a command makes, without the disk: simulate hands back the
// very bytes `rotleak simulate` writes (io run_texts), omega and covering their JSON documents. The GIL
// is released while a run works; Ctrl-C stops it between blocks (KeyboardInterrupt); progress goes to
// a Python callable. Bad input raises ValueError with the command line's one-line message.
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <csignal>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/output/covering_output.hpp"
#include "analysis/output/omega_output.hpp"
#include "analysis/output/run_output.hpp"
#include "analysis/output/table_output.hpp"
#include "io/scene_file.hpp"
#include "numeric/input.hpp"
#include "run/calibrate.hpp"
#include "run/pipeline.hpp"
#include "run/refit.hpp"
#include "run/regimes_search.hpp"
#include "run/scan.hpp"
#include "version.hpp"

namespace py = pybind11;

namespace {

std::atomic<bool> g_interrupt{false};
extern "C" void on_sigint(int) { g_interrupt.store(true); }

/// While a run works without the GIL, SIGINT sets g_interrupt (Python's own handler would only run
/// once the run is over); the caller's handler comes back afterwards. Only the main thread handles
/// signals, so only there is a handler installed.
class SigintGuard {
 public:
  explicit SigintGuard(bool main_thread) : active_(main_thread) {
    g_interrupt.store(false);
    if (!active_) return;
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_);
  }
  ~SigintGuard() {
    if (active_) sigaction(SIGINT, &old_, nullptr);
  }
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  bool active_;
  struct sigaction old_ {};
};

bool in_main_thread() {
  py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

/// work() run without the GIL, SIGINT noted in g_interrupt (the work's progress callback turns it into its
/// stop flag); empty when the work was stopped between blocks (RunInterrupted).
template <class Result, class Work>
std::optional<Result> run_released(Work&& work) {
  std::optional<Result> result;
  SigintGuard guard(in_main_thread());
  py::gil_scoped_release released;
  try {
    result = work();
  } catch (const rotleak::RunInterrupted&) {
    // the caller raises KeyboardInterrupt, with the GIL
  }
  return result;
}

[[noreturn]] void raise_keyboard_interrupt(const char* message) {
  PyErr_SetString(PyExc_KeyboardInterrupt, message);
  throw py::error_already_set();
}

/// (name, bytes) of every file of the run, as the run directory would hold them.
/// Where a Python Scene's runs say they came from (summary.json's scene.source, the header line).
constexpr const char* kPythonSource = "rotleak.Scene";

/// A scene file with overrides, or (is_text) a Python Scene's TOML text with them: one reader for both.
rotleak::Scene scene_of(const std::string& scene, bool is_text, const std::vector<std::string>& overrides) {
  return is_text ? rotleak::parse_scene(scene, overrides, kPythonSource) : rotleak::load_scene(scene, overrides);
}

/// A scene's TOML text with overrides, read and checked by the file's reader (its one-line errors), written back
/// as rotleak writes scene.toml: what rotleak.Scene holds.
std::string scene_toml(const std::string& text, const std::vector<std::string>& overrides) {
  return rotleak::scene_to_toml(rotleak::parse_scene(text, overrides, kPythonSource));
}

py::list simulate(const std::string& scene_path, const std::vector<std::string>& overrides, int threads,
                  const std::optional<py::function>& progress, bool scene_is_text) {
  if (threads < 0) throw rotleak::InputError("threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  rotleak::Scene scene = scene_of(scene_path, scene_is_text, overrides);
  rotleak::RunOptions opt;
  opt.threads = threads;
  std::atomic<bool> stop{false};
  opt.stop = &stop;
  // the caller's progress callable, under the GIL; an exception it raises stops the run and is raised
  std::unique_ptr<py::error_already_set> raised;
  opt.progress = [&](std::uint64_t done, std::uint64_t total, std::uint64_t collisions, bool final) {
    if (g_interrupt.load()) stop.store(true);
    if (!progress || raised) return;
    py::gil_scoped_acquire gil;
    try {
      (*progress)(done, total, collisions, final);
    } catch (py::error_already_set& e) {
      raised = std::make_unique<py::error_already_set>(std::move(e));
      stop.store(true);
    }
  };
  const std::optional<rotleak::RunSummary> summary = run_released<rotleak::RunSummary>(
      [&] { return rotleak::run_scene(rotleak::plan_run(std::move(scene), opt), opt); });
  if (raised) throw std::move(*raised);
  if (!summary) raise_keyboard_interrupt("rotleak.simulate interrupted: the run was stopped between blocks");
  const rotleak::RunTexts texts = rotleak::run_files(*summary, summary->scene.particles, false);
  py::list out;
  for (const auto& [name, text] : texts.files) out.append(py::make_tuple(name, py::bytes(text)));
  return out;
}

/// The run options of a command that runs many scenes (calibrate, scan, regimes) from Python: threads checked,
/// Ctrl-C noted between blocks (g_interrupt sets `stop`), and `note` (may be None) called with each status line.
rotleak::RunOptions looped_run(int threads, std::atomic<bool>& stop) {
  if (threads < 0) throw rotleak::InputError("threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  rotleak::RunOptions run;
  run.threads = threads;
  run.stop = &stop;
  run.progress = [&stop](std::uint64_t, std::uint64_t, std::uint64_t, bool) {
    if (g_interrupt.load()) stop.store(true);
  };
  return run;
}

/// A request's scene: a file, or (is_text) a Python Scene's TOML text named kPythonSource, with overrides.
template <class Request>
void scene_into(Request& req, const std::string& scene, bool is_text, const std::vector<std::string>& overrides) {
  req.scene_path = is_text ? kPythonSource : scene;
  if (is_text) req.scene_text = scene;
  req.overrides = overrides;
}

/// A Python callable (or None) as the library's Note: each line handed over under the GIL.
rotleak::Note python_note(const std::optional<py::function>& note) {
  if (!note) return {};
  return [note](const std::string& line) {
    py::gil_scoped_acquire gil;
    (*note)(line);
  };
}

/// `rotleak calibrate` into `out`: the seeds' runs (those complete skipped), calibration.csv and
/// calibration.json; returns calibration.json's text. Ctrl-C stops it between blocks (its points are kept).
std::string calibrate(const std::string& scene, const std::vector<std::string>& overrides, std::uint64_t seeds,
                      std::uint64_t first_seed, const std::string& out, int threads, bool force, bool scene_is_text) {
  std::atomic<bool> stop{false};
  rotleak::CalibrateRequest req;
  req.run = looped_run(threads, stop);
  scene_into(req, scene, scene_is_text, overrides);
  req.seeds = seeds;
  req.first_seed = first_seed;
  req.out = out;
  req.force = force;
  const std::optional<rotleak::CalibrateOutcome> outcome =
      run_released<rotleak::CalibrateOutcome>([&] { return rotleak::calibrate(req); });
  if (!outcome) raise_keyboard_interrupt("rotleak.calibrate interrupted: the seeds done so far are kept");
  return outcome->document.dump();
}

/// `rotleak scan` into `out`, the axes as --over's KEY=VALUES texts; returns scan.json's text. Points complete
/// there are kept; Ctrl-C stops it between blocks (the points done are kept, the one running resumes).
std::string scan(const std::string& scene, const std::vector<std::string>& overrides,
                 const std::vector<std::string>& over, const std::string& out, int threads, bool force,
                 bool scene_is_text, const std::optional<py::function>& note) {
  std::atomic<bool> stop{false};
  rotleak::ScanRequest req;
  req.run = looped_run(threads, stop);
  scene_into(req, scene, scene_is_text, overrides);
  for (const std::string& o : over) req.axes.push_back(rotleak::parse_axis(o));
  req.out = out;
  req.force = force;
  req.note = python_note(note);
  const std::optional<rotleak::ScanOutcome> outcome =
      run_released<rotleak::ScanOutcome>([&] { return rotleak::scan(req); });
  if (!outcome) raise_keyboard_interrupt("rotleak.scan interrupted: the points done so far are kept");
  return outcome->document.dump();
}

/// `rotleak regimes` into `out`; returns regimes.json's text.
std::string regimes(const std::string& scene, const std::vector<std::string>& overrides, const std::string& coarse,
                    int steps, const std::string& out, int threads, bool scene_is_text,
                    const std::optional<py::function>& note) {
  if (steps < 0 || steps > 30) throw rotleak::InputError("steps", std::to_string(steps), "must be in [0, 30]");
  std::atomic<bool> stop{false};
  rotleak::RegimesRequest req;
  req.run = looped_run(threads, stop);
  scene_into(req, scene, scene_is_text, overrides);
  req.coarse = coarse;
  req.steps = steps;
  req.out = out;
  req.note = python_note(note);
  const std::optional<rotleak::json> doc = run_released<rotleak::json>([&] { return rotleak::find_regimes(req); });
  if (!doc) raise_keyboard_interrupt("rotleak.regimes interrupted: the probes done so far are kept");
  return doc->dump();
}

/// `rotleak fit DIR`: a run or a scan refitted under fit.* overrides; returns (is a scan, the new summary.json or
/// scan.json text, a run's fit lines as simulate prints them).
py::tuple fit(const std::string& dir, const std::vector<std::string>& overrides,
              const std::optional<py::function>& note) {
  const rotleak::Note n = python_note(note);
  rotleak::RefitOutcome out;
  {
    py::gil_scoped_release released;
    out = rotleak::refit(dir, overrides, n);
  }
  return py::make_tuple(out.scan, out.document.dump(), out.text);
}

std::string omega(const std::string& value, long long terms, const std::string& max_den, const std::string& eps,
                  int digits, int convergents) {
  rotleak::OmegaRequest r;
  r.value = value;
  r.terms = terms;
  r.max_den = max_den;
  r.eps = eps;
  r.digits = digits;
  r.convergents = convergents;
  rotleak::OmegaReport report;
  {
    py::gil_scoped_release released;
    report = rotleak::compute_omega(r);
  }
  return rotleak::omega_json(report, eps).dump();
}

/// summary.json's document, f_L.csv at `resolution` bins, and each covering's segments csv.
/// `rotleak predict --json`'s document for a scene file with overrides (milliseconds: the GIL is kept).
std::string predict(const std::string& scene, const std::vector<std::string>& overrides, bool scene_is_text) {
  const rotleak::Scene sc = scene_of(scene, scene_is_text, overrides);
  rotleak::require_stadium(sc, "rotleak.predict");
  return rotleak::prediction_document(sc, rotleak::predict_tail(sc)).dump(2);
}

std::string table_drawing(const std::string& scene, const std::vector<std::string>& overrides, int samples,
                          bool scene_is_text) {
  if (samples < 8 || samples > 1000000)
    throw rotleak::InputError("samples", std::to_string(samples), "must be in [8, 10^6]");
  return rotleak::table_drawing(scene_of(scene, scene_is_text, overrides), samples).dump();
}

py::tuple covering(const std::vector<std::string>& omegas, const std::vector<std::string>& deltas,
                   const std::string& lambda, const std::string& d, const std::string& r, int resolution) {
  if (resolution < 1 || resolution > 10000000)
    throw rotleak::InputError("resolution", std::to_string(resolution), "must be in [1, 10^7]");
  rotleak::CoveringRequest req;
  req.omegas = omegas;
  req.deltas = deltas;
  req.lambda = lambda;
  req.d = d;
  req.r = r;
  std::string doc, profile;
  std::vector<std::string> segments;
  {
    py::gil_scoped_release released;
    const rotleak::CoveringOutcome c = rotleak::compute_coverings(req);
    doc = c.document.dump();
    profile = rotleak::covering_profile_csv(c.labels, c.results, static_cast<std::size_t>(resolution));
    for (const auto& one : c.results) segments.push_back(rotleak::covering_segments_csv(one));
  }
  return py::make_tuple(doc, profile, segments);
}

}  // namespace

PYBIND11_MODULE(_rotleak, m) {
  m.doc() = "rotleak's library in process (use the package rotleak, which wraps this module)";
  m.attr("version") = rotleak::kVersion;
  m.attr("git") = rotleak::kGitDescribe;
  // an InputError is the caller's mistake: ValueError with the one-line message
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const rotleak::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def("simulate", &simulate, py::arg("scene"), py::arg("overrides"), py::arg("threads"), py::arg("progress"),
        py::arg("scene_is_text") = false,
        "Runs a scene (a file, or TOML text) in process; returns [(file name, bytes)] as `rotleak simulate` would "
        "write them.");
  m.def("scene_toml", &scene_toml, py::arg("text"), py::arg("overrides"),
        "A scene's TOML text with overrides, checked by rotleak's reader and written as scene.toml is.");
  m.def("calibrate", &calibrate, py::arg("scene"), py::arg("overrides"), py::arg("seeds"), py::arg("first_seed"),
        py::arg("out"), py::arg("threads"), py::arg("force"), py::arg("scene_is_text") = false,
        "Runs `rotleak calibrate` into a directory; returns calibration.json's text.");
  m.def("scan", &scan, py::arg("scene"), py::arg("overrides"), py::arg("over"), py::arg("out"), py::arg("threads"),
        py::arg("force"), py::arg("scene_is_text") = false, py::arg("note") = py::none(),
        "Runs `rotleak scan` into a directory; returns scan.json's text.");
  m.def("regimes", &regimes, py::arg("scene"), py::arg("overrides"), py::arg("coarse"), py::arg("steps"),
        py::arg("out"), py::arg("threads"), py::arg("scene_is_text") = false, py::arg("note") = py::none(),
        "Runs `rotleak regimes` into a directory; returns regimes.json's text.");
  m.def("fit", &fit, py::arg("dir"), py::arg("overrides"), py::arg("note") = py::none(),
        "`rotleak fit DIR`: (is a scan, the new summary.json or scan.json text, a run's fit lines).");
  m.def("omega", &omega, py::arg("value"), py::arg("terms"), py::arg("max_den"), py::arg("eps"), py::arg("digits"),
        py::arg("convergents"), "`rotleak omega --json`'s document as a JSON text.");
  m.def("predict", &predict, py::arg("scene"), py::arg("overrides"), py::arg("scene_is_text") = false,
        "The covering model's tail for a scene: rotleak predict --json's document");
  m.def("table_drawing", &table_drawing, py::arg("scene"), py::arg("overrides"), py::arg("samples"),
        py::arg("scene_is_text") = false,
        "The scene's table as points to draw (analysis/output/table_output.hpp), as a JSON text.");
  m.def("covering", &covering, py::arg("omegas"), py::arg("deltas"), py::arg("lam"), py::arg("d"), py::arg("r"),
        py::arg("resolution"), "(summary.json text, f_L.csv text, [segments csv]) of `rotleak covering`.");
}
