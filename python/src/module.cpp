// lightbench._core: the C++ side of the Python package (python/lightbench/).
// Thin bindings only: scene loading, rendering, EXR files, error metrics and
// experiments are the same code the `lightbench` program runs, so a render from
// Python equals the CLI's bit for bit at the same seed. The Pythonic surface
// (keyword arguments, dicts, DataFrames) is in python/lightbench/*.py.
#include <pybind11/numpy.h>
#include <optional>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <algorithm>
#include <cstring>
#include "core/error.h"
#include "core/image.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/experiment.h"
#include "experiments/json_values.h"
#include "experiments/metrics.h"
#include "experiments/runner.h"
#include "integrators/registry.h"

namespace py = pybind11;
using namespace lb;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// (height, width, 3) float32, row 0 at the top: the EXR's layout.
FloatArray toArray(const Image& image) {
  FloatArray a({size_t(image.height), size_t(image.width), size_t(3)});
  static_assert(sizeof(Color) == 3 * sizeof(float), "Color is three packed floats");
  std::memcpy(a.mutable_data(), image.pixels.data(), image.pixels.size() * sizeof(Color));
  return a;
}

Image toImage(const FloatArray& a, const char* what) {
  if (a.ndim() != 3 || a.shape(2) != 3)
    throw py::value_error(std::string(what) + ": expected an array of shape (height, width, 3)");
  // An error of no pixels is no error (rmse of empty arrays was 0.0).
  if (a.shape(0) == 0 || a.shape(1) == 0)
    throw py::value_error(std::string(what) + ": an empty array (no pixels)");
  Image image(int(a.shape(1)), int(a.shape(0)));
  std::memcpy(image.pixels.data(), a.data(), image.pixels.size() * sizeof(Color));
  return image;
}

py::dict reportDict(const RenderReport& r) {
  py::dict d;
  d["spp"] = r.passes;
  d["seconds"] = r.seconds;
  d["preprocess_seconds"] = r.preprocessSeconds;
  d["rays"] = r.rays;
  d["non_finite_samples"] = r.nonFinite;
  d["over_budget_seconds"] = r.overBudgetSeconds();
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "lightbench's C++ core (use the lightbench package, not this module)";
  // Bad input (file:line: key: message) is a ValueError subclass in Python.
  py::register_exception<ConfigError>(m, "ConfigError", PyExc_ValueError);

  m.def("version", &versionString);

  m.def(
      "render",
      [](const std::string& scene, const std::string& integrator, const std::vector<std::string>& overrides,
         uint64_t spp, double seconds, uint64_t seed, int threads, bool progress, const std::vector<std::string>& aovs,
         const std::string& resolution, const std::string& crop) {
        RenderArgs args;
        args.resolution = resolution, args.crop = crop;
        args.scene = scene, args.integrator = integrator, args.overrides = overrides, args.aovs = aovs;
        for (const auto& a : aovs)
          if (std::find(aovNames().begin(), aovNames().end(), a) == aovNames().end())
            throw py::value_error("unknown AOV '" + a + "'");
        args.spp = spp, args.seconds = seconds, args.seed = seed, args.threads = threads, args.quiet = !progress;
        // Ctrl-C: Python's handler only sets a flag, run here between passes
        // (on this, the main, thread), which raises KeyboardInterrupt.
        args.betweenPasses = [] {
          py::gil_scoped_acquire locked;
          if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        };
        RenderedImage r;
        {
          py::gil_scoped_release unlocked;  // a render takes seconds; other Python threads may run
          r = renderToMemory(args);
        }
        py::dict layers;
        for (const ExrLayer& l : r.layers) layers[py::str(l.name)] = toArray(l.image);
        // The resolved configuration as JSON (json.loads in Python: no YAML module needed).
        std::string resolved = yamlToJson(r.resolved).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        return py::make_tuple(toArray(r.image), resolved, reportDict(r.report), layers);
      },
      py::arg("scene"), py::arg("integrator"), py::arg("overrides"), py::arg("spp"), py::arg("seconds"),
      py::arg("seed"), py::arg("threads"), py::arg("progress"), py::arg("aovs"), py::arg("resolution"),
      py::arg("crop"));
  // One checker for render()'s arguments and `lightbench render`'s flags: the
  // argument, as the flag's text, goes through the flag's own check.
  m.def(
      "check_render_argument",
      [](const std::string& flag, std::string text, const std::string& argument) {
        std::string problem = renderFlagCheck(flag)(text);
        if (!problem.empty()) throw ConfigError("render()", 0, argument, problem);
      },
      py::arg("flag"), py::arg("text"), py::arg("argument"));
  m.def("read_exr_layer", [](const std::string& path, const std::string& layer) { return toArray(readExrLayer(path, layer)); },
        py::arg("path"), py::arg("layer"));
  m.def("read_exr_attributes", &readExrAttributes, py::arg("path"));

  m.def("read_exr", [](const std::string& path) { return toArray(readExr(path)); }, py::arg("path"));
  m.def("write_exr", [](const std::string& path, const FloatArray& a) { writeExr(path, toImage(a, "write_exr")); },
        py::arg("path"), py::arg("image"));

  m.def(
      "metrics",
      [](const FloatArray& image, const FloatArray& reference, float epsilon, std::vector<int> crop,
         std::optional<FloatArray> referenceVariance, float trimFraction) {
        Image x = toImage(image, "image"), r = toImage(reference, "reference");
        if (x.width != r.width || x.height != r.height) throw py::value_error("image and reference differ in size");
        Image v;
        if (referenceVariance) {
          v = toImage(*referenceVariance, "reference_variance");
          if (v.width != r.width || v.height != r.height)
            throw py::value_error("reference_variance and reference differ in size");
        }
        if (!(trimFraction >= 0 && trimFraction < 0.5f)) throw py::value_error("fraction: must be in [0, 0.5)");
        Crop c;
        if (crop.size() == 4) c = {crop[0], crop[1], crop[2], crop[3]};
        else if (!crop.empty()) throw py::value_error("crop: expected (x0, y0, x1, y1)");
        // computeMetrics reads the crop's pixels unchecked.
        if (!crop.empty() && !(0 <= c.x0 && c.x0 < c.x1 && c.x1 <= x.width && 0 <= c.y0 && c.y0 < c.y1 && c.y1 <= x.height))
          throw py::value_error("crop: need 0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height");
        MetricSettings settings;
        settings.relEpsilon = epsilon;
        settings.trimFraction = trimFraction;
        ErrorMetrics e = computeMetrics(x, r, settings, c, v);
        return py::make_tuple(e.rmse, e.relMse, e.mape, e.relMseTrimmed, e.mseCorrected, e.relMseCorrected,
                              e.relMseTrimmedCorrected);
      },
      py::arg("image"), py::arg("reference"), py::arg("epsilon"), py::arg("crop"),
      py::arg("reference_variance") = std::nullopt, py::arg("trim_fraction") = 1e-3f);

  m.def(
      "run_experiment",
      [](const std::string& path, bool quick, bool resume, int jobs, const std::string& results, bool report,
         const std::string& python) {
        ExperimentOptions eo;
        eo.quick = quick;
        Experiment e = loadExperiment(path, eo);
        RunnerOptions ro;
        ro.resultsRoot = results, ro.resume = resume, ro.jobs = jobs, ro.report = report, ro.python = python;
        py::gil_scoped_release unlocked;
        return runExperiment(e, ro);
      },
      py::arg("path"), py::arg("quick"), py::arg("resume"), py::arg("jobs"), py::arg("results"), py::arg("report"),
      py::arg("python"));

  m.def("slug", &slug, py::arg("label"));
  m.def("integrator_names", [] {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& e : integratorRegistry()) out.emplace_back(e.name, e.summary);
    return out;
  });
  m.def(
      "integrator_keys",
      [](const std::string& name) {
        py::list out;
        for (const KeyDoc& k : integratorKeys(name)) {
          py::dict d;
          d["key"] = k.key, d["type"] = k.type, d["default"] = k.fallback, d["allowed"] = k.allowed;
          d["meaning"] = k.meaning, d["condition"] = k.condition;
          out.append(d);
        }
        return out;
      },
      py::arg("name"));
}
