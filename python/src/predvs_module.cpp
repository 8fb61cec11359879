// predvs._predvs — the Python extension behind `import predvs` (issue 13 item 3, docs/PYTHON.md).
//
// A thin binding, no logic of its own: the predictor registry (predictors/.../predictor.h), the
// noise fit (calibration/noise_fit.h) and the parameter file (calibration/param_file.h), under
// the C++ names in snake_case. Errors are the C++ ones: std::invalid_argument becomes ValueError
// with the same message (pybind11's translation); an index out of range raises IndexError.
//
// Conventions on the Python side (units as in C++: px, px/s, px/s^2, seconds):
//  * params: a dict KEY -> number (int or float) or the word "auto" (kept as text, as in a
//    parameter file); any other value raises ValueError naming the key.
//  * Predictor.predict(t) -> (x, P): x float64 (channels, n_state), P (channels, n_state, n_state),
//    n_state = 2 ([p, v]) or 3 ([p, v, a]) for the predictor; an uninitialised channel is all NaN.
//    predict(t, channel=c) -> (x (n_state,), P (n_state, n_state)) for one channel.
//  * update(t, z): z a sequence / 1-D array of `channels` floats, NaN = channel not measured;
//    update(t) (z None) is the predict-only step.
//  * fit_noise / log_likelihood take t (frames,) and z (frames, channels) or (frames,) for one
//    channel, NaN where not measured, as a track's rows.
#include "predvs/calibration/noise_fit.h"
#include "predvs/calibration/param_file.h"
#include "predvs/predictors/predictor.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace predvs;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Params paramsFromDict(const py::dict& d, const std::string& what) {
  Params p;
  for (const auto& kv : d) {
    if (!py::isinstance<py::str>(kv.first))
      throw std::invalid_argument(what + ": parameter names must be strings, got " +
                                  std::string(py::str(py::repr(kv.first))));
    const std::string key = kv.first.cast<std::string>();
    const py::handle v = kv.second;
    if (py::isinstance<py::bool_>(v))
      throw std::invalid_argument("parameter '" + key + "' of " + what + ": expected a number, got a bool");
    if (py::isinstance<py::str>(v)) {
      p.setText(key, v.cast<std::string>());  // a word (r: auto, model: ca, mean: zero): the predictor checks it
      continue;
    }
    double x = 0.0;
    try {
      x = py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
    } catch (const py::error_already_set&) {
      throw std::invalid_argument("parameter '" + key + "' of " + what + ": expected a number, got " +
                                  std::string(py::str(py::repr(v))));
    }
    if (!std::isfinite(x)) throw std::invalid_argument("parameter '" + key + "' of " + what + ": expected a finite number");
    p.set(key, x);
  }
  return p;
}

py::dict paramsToDict(const Params& p) {
  py::dict d;
  for (const auto& kv : p.values()) d[py::str(kv.first)] = kv.second;
  for (const auto& kv : p.texts()) d[py::str(kv.first)] = kv.second;
  return d;
}

/// Builds a checked Params for `name` (unknown predictor / key -> the registry's ValueError).
Params checkedParams(const std::string& name, const py::object& params) {
  Params p;
  if (!params.is_none()) {
    if (!py::isinstance<py::dict>(params)) throw std::invalid_argument(name + ": params must be a dict KEY -> value");
    p = paramsFromDict(params.cast<py::dict>(), name);
  }
  return p;
}

/// t (frames,) and z (frames, channels) or (frames,) -> a FitTrack; NaN = not measured.
FitTrack fitTrackOf(const py::object& t_obj, const py::object& z_obj) {
  const auto t = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(t_obj);
  const auto z = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(z_obj);
  if (!t || t.ndim() != 1) throw std::invalid_argument("t: expected a 1-D array of frame times (s)");
  if (!z || (z.ndim() != 1 && z.ndim() != 2))
    throw std::invalid_argument("z: expected a 2-D array (frames, channels), NaN where not measured");
  const py::ssize_t frames = t.shape(0);
  if (z.shape(0) != frames)
    throw std::invalid_argument("z: " + std::to_string(z.shape(0)) + " rows, expected one per time (" +
                                std::to_string(frames) + ")");
  const py::ssize_t channels = z.ndim() == 2 ? z.shape(1) : 1;
  if (channels < 1) throw std::invalid_argument("z: expected at least one channel");
  FitTrack track;
  const double* tp = t.data();
  track.t_s.assign(tp, tp + frames);
  for (py::ssize_t k = 0; k < frames; ++k) {
    if (!std::isfinite(track.t_s[static_cast<size_t>(k)]))
      throw std::invalid_argument("t: row " + std::to_string(k) + ": expected a finite time");
    if (k > 0 && !(track.t_s[static_cast<size_t>(k)] > track.t_s[static_cast<size_t>(k - 1)]))
      throw std::invalid_argument("t: row " + std::to_string(k) + ": times must be strictly increasing");
  }
  const double* zp = z.data();
  track.channels.assign(static_cast<size_t>(channels), std::vector<double>(static_cast<size_t>(frames)));
  for (py::ssize_t k = 0; k < frames; ++k)
    for (py::ssize_t c = 0; c < channels; ++c) {
      const double v = zp[k * channels + c];
      if (std::isinf(v))
        throw std::invalid_argument("z: row " + std::to_string(k) + ", channel " + std::to_string(c) +
                                    ": expected a finite value or NaN");
      track.channels[static_cast<size_t>(c)][static_cast<size_t>(k)] = v;
    }
  return track;
}

/// Python-side predictor: owns the C++ predictor, checks sizes and indices.
class PyPredictor {
 public:
  PyPredictor(const std::string& name, int channels, const py::object& params)
      : params_(checkedParams(name, params)) {
    p_ = makePredictor(name, channels, params_);
  }

  std::string name() const { return p_->name(); }
  int channels() const { return p_->channels(); }
  double time() const { return p_->time(); }
  py::dict params() const { return paramsToDict(params_); }
  void reset() { p_->reset(); }

  void update(double t_s, const py::object& z_obj) {
    if (z_obj.is_none()) {
      p_->update(t_s);
      return;
    }
    const auto z = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(z_obj);
    if (!z || z.ndim() != 1 || z.shape(0) != p_->channels())
      throw std::invalid_argument(p_->name() + ": update: z must hold " + std::to_string(p_->channels()) +
                                  " values (one per channel, NaN = not measured)");
    const Eigen::Map<const Eigen::VectorXd> zv(z.data(), p_->channels());
    p_->update(t_s, zv);
  }

  int stateSize(double t_s) const {
    int n = 0;
    for (int c = 0; c < p_->channels(); ++c) n = std::max(n, static_cast<int>(p_->predict(c, t_s).x.size()));
    return n;
  }

  py::tuple predictChannel(double t_s, int c) const {
    checkChannel(c);
    const ChannelEstimate e = p_->predict(c, t_s);
    const auto n = static_cast<py::ssize_t>(e.x.size());
    py::array_t<double> x(n), P({n, n});
    auto xm = x.mutable_unchecked<1>();
    auto Pm = P.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      xm(i) = e.x(i);
      for (py::ssize_t j = 0; j < n; ++j) Pm(i, j) = e.P(i, j);
    }
    return py::make_tuple(x, P);
  }

  py::tuple predictAll(double t_s) const {
    const int m = p_->channels();
    std::vector<ChannelEstimate> es;
    py::ssize_t n = 0;
    for (int c = 0; c < m; ++c) {
      es.push_back(p_->predict(c, t_s));
      n = std::max<py::ssize_t>(n, es.back().x.size());
    }
    py::array_t<double> x({static_cast<py::ssize_t>(m), n}), P({static_cast<py::ssize_t>(m), n, n});
    auto xm = x.mutable_unchecked<2>();
    auto Pm = P.mutable_unchecked<3>();
    for (int c = 0; c < m; ++c) {
      const auto& e = es[static_cast<size_t>(c)];
      const auto nc = static_cast<py::ssize_t>(e.x.size());
      for (py::ssize_t i = 0; i < n; ++i) {
        xm(c, i) = i < nc ? e.x(i) : kNaN;
        for (py::ssize_t j = 0; j < n; ++j) Pm(c, i, j) = (i < nc && j < nc) ? e.P(i, j) : kNaN;
      }
    }
    return py::make_tuple(x, P);
  }

  py::tuple predict(double t_s, std::optional<int> channel) const {
    return channel ? predictChannel(t_s, *channel) : predictAll(t_s);
  }

  py::array_t<double> predictPositions(double t_s) const { return toArray(p_->predictPositions(t_s)); }
  py::array_t<double> predictVelocities(double t_s) const { return toArray(p_->predictVelocities(t_s)); }
  py::array_t<double> feedforwardVelocities(double t_s) const { return toArray(p_->feedforwardVelocities(t_s)); }

  Innovation innovation(int c) const {
    checkChannel(c);
    return p_->innovation(c);
  }

  py::dict diagnostics() const {
    py::dict d;
    for (const auto& kv : p_->diagnostics()) d[py::str(kv.first)] = kv.second;
    return d;
  }
  std::vector<NoiseParameter> noiseParameters() const { return p_->noiseParameters(); }
  bool extrapolates() const { return p_->extrapolates(); }
  int monitorAlarms() const { return p_->monitorAlarms(); }

 private:
  void checkChannel(int c) const {
    if (c < 0 || c >= p_->channels())
      throw py::index_error(p_->name() + ": channel " + std::to_string(c) + " out of range [0, " +
                            std::to_string(p_->channels()) + ")");
  }
  static py::array_t<double> toArray(const Eigen::VectorXd& v) {
    py::array_t<double> a(v.size());
    std::copy(v.data(), v.data() + v.size(), a.mutable_data());
    return a;
  }

  Params params_;
  std::unique_ptr<Predictor> p_;
};

py::list entriesToList(const std::vector<ParamFileEntry>& entries) {
  py::list out;
  for (const auto& e : entries) {
    py::dict d;
    d["name"] = e.name;
    d["params"] = paramsToDict(e.params);
    out.append(d);
  }
  return out;
}

std::vector<ParamFileEntry> entriesFromList(const py::iterable& items) {
  std::vector<ParamFileEntry> out;
  for (const auto& item : items) {
    if (!py::isinstance<py::dict>(item) || !item.cast<py::dict>().contains("name"))
      throw std::invalid_argument("params_file_text: each entry must be a dict {'name': PREDICTOR, 'params': {...}}");
    const py::dict d = item.cast<py::dict>();
    ParamFileEntry e;
    e.name = py::str(d["name"]).cast<std::string>();
    if (!isPredictor(e.name)) makePredictor(e.name, 1);  // throws the registry's "unknown predictor" message
    if (d.contains("params")) e.params = checkedParams(e.name, d["params"]);
    makePredictor(e.name, 2, e.params);  // an unknown or out-of-range key raises here, as when reading
    out.push_back(e);
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_predvs, m) {
  m.doc() = "predvs: the predictor registry, the noise fit and the parameter file of predvs (docs/PYTHON.md)";

  m.def(
      "predictors",
      [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& i : predictorRegistry()) out.emplace_back(i.name, i.summary);
        return out;
      },
      "Every registered predictor as (name, summary), in display order (`predvs list`).");
  m.def("is_predictor", &isPredictor, py::arg("name"), "True if `name` is a registered predictor.");

  py::class_<Innovation>(m, "Innovation", "Innovation of the last update of one channel: eps = z - H x(k|k-1), "
                                          "S = H P(k|k-1) H' + R; valid is False when it was not measured.")
      .def_readonly("eps", &Innovation::eps)
      .def_readonly("S", &Innovation::S)
      .def_readonly("valid", &Innovation::valid)
      .def("__repr__", [](const Innovation& i) {
        return "Innovation(eps=" + std::string(py::str(py::float_(i.eps))) + ", S=" +
               std::string(py::str(py::float_(i.S))) + ", valid=" + (i.valid ? "True" : "False") + ")";
      });

  py::class_<NoiseParameter>(m, "NoiseParameter",
                             "A key that sets process or measurement noise, its fit bounds [lo, hi] and its value.")
      .def_readonly("key", &NoiseParameter::key)
      .def_readonly("lo", &NoiseParameter::lo)
      .def_readonly("hi", &NoiseParameter::hi)
      .def_readonly("value", &NoiseParameter::value)
      .def("__repr__", [](const NoiseParameter& p) {
        return "NoiseParameter(key='" + p.key + "', lo=" + std::string(py::str(py::float_(p.lo))) +
               ", hi=" + std::string(py::str(py::float_(p.hi))) + ", value=" + std::string(py::str(py::float_(p.value))) + ")";
      });

  py::class_<PyPredictor>(m, "Predictor", "A predictor of the registry over `channels` scalar channels (predvs.make).")
      .def(py::init<const std::string&, int, const py::object&>(), py::arg("name"), py::arg("channels"),
           py::arg("params") = py::none())
      .def_property_readonly("name", &PyPredictor::name)
      .def_property_readonly("channels", &PyPredictor::channels)
      .def_property_readonly("time", &PyPredictor::time, "time of the last update, s (NaN before the first)")
      .def_property_readonly("params", &PyPredictor::params, "the params it was built with")
      .def("reset", &PyPredictor::reset, "Back to the state after construction.")
      .def("update", &PyPredictor::update, py::arg("t"), py::arg("z") = py::none(),
           "Predict to the acquisition time t (s) and fuse z (one value per channel, NaN = not measured); "
           "update(t) alone is predict-only. Times must increase strictly (ValueError otherwise).")
      .def("predict", &PyPredictor::predict, py::arg("t"), py::arg("channel") = py::none(),
           "(x, P) at time t without changing the filter: x (channels, n_state), P (channels, n_state, n_state); "
           "with channel=c, x (n_state,) and P (n_state, n_state).")
      .def("predict_positions", &PyPredictor::predictPositions, py::arg("t"), "Predicted positions at t, (channels,).")
      .def("predict_velocities", &PyPredictor::predictVelocities, py::arg("t"), "Predicted velocities at t, (channels,).")
      .def("feedforward_velocities", &PyPredictor::feedforwardVelocities, py::arg("t"),
           "Velocities at t for a control law's feed-forward: the filter's own, judged over about a second instead of "
           "scaled by the forecast's blend with hold, and not weighted by their significance, (channels,).")
      .def("innovation", &PyPredictor::innovation, py::arg("channel"), "Innovation of the last update of a channel.")
      .def("diagnostics", &PyPredictor::diagnostics, "Named per-channel internals after the last update (dict).")
      .def("noise_parameters", &PyPredictor::noiseParameters, "The keys that set its noise, with bounds and values.")
      .def_property_readonly("extrapolates", &PyPredictor::extrapolates)
      .def_property_readonly("monitor_alarms", &PyPredictor::monitorAlarms)
      .def("__repr__", [](const PyPredictor& p) {
        return "<predvs.Predictor '" + p.name() + "', " + std::to_string(p.channels()) + " channels>";
      });

  m.def(
      "make", [](const std::string& name, int channels, const py::object& params) {
        return PyPredictor(name, channels, params);
      },
      py::arg("name"), py::arg("channels"), py::arg("params") = py::none(),
      "Builds the predictor `name` for `channels` channels with params {KEY: value}. ValueError names an "
      "unknown predictor or an unknown / out-of-range key.");

  py::class_<FittedValue>(m, "FittedValue", "One fitted key: start, fitted value, std of log(value), 95 % interval.")
      .def_readonly("key", &FittedValue::key)
      .def_readonly("initial", &FittedValue::initial)
      .def_readonly("value", &FittedValue::value)
      .def_readonly("std_log", &FittedValue::std_log)
      .def_readonly("lo95", &FittedValue::lo95)
      .def_readonly("hi95", &FittedValue::hi95)
      .def_readonly("at_bound", &FittedValue::at_bound)
      .def_readonly("held", &FittedValue::held, "not fitted: kept at `initial` (r under the prediction objective)")
      .def("__repr__", [](const FittedValue& v) {
        return "FittedValue(key='" + v.key + "', initial=" + std::string(py::str(py::float_(v.initial))) +
               ", value=" + std::string(py::str(py::float_(v.value))) + ", std_log=" +
               std::string(py::str(py::float_(v.std_log))) + ", at_bound=" + (v.at_bound ? "True" : "False") + ")";
      });

  py::class_<NoiseFitResult>(m, "NoiseFitResult", "Result of fit_noise (calibration/noise_fit.h NoiseFitResult).")
      .def_readonly("predictor", &NoiseFitResult::predictor)
      .def_property_readonly("params", [](const NoiseFitResult& r) { return paramsToDict(r.params); },
                             "base params with the fitted keys set (dict)")
      .def_readonly("values", &NoiseFitResult::values)
      .def_readonly("loglik_before", &NoiseFitResult::loglik_before)
      .def_readonly("loglik_after", &NoiseFitResult::loglik_after)
      .def_readonly("innovations", &NoiseFitResult::innovations)
      .def_readonly("iterations", &NoiseFitResult::iterations)
      .def_readonly("termination", &NoiseFitResult::termination)
      .def_readonly("covariance_ok", &NoiseFitResult::covariance_ok)
      .def_property_readonly("objective", [](const NoiseFitResult& r) { return fitObjectiveName(r.objective); })
      .def_readonly("horizon_s", &NoiseFitResult::horizon_s)
      .def_readonly("residuals", &NoiseFitResult::residuals)
      .def_readonly("rmse_before_px", &NoiseFitResult::rmse_before_px)
      .def_readonly("rmse_after_px", &NoiseFitResult::rmse_after_px)
      .def_readonly("variant", &NoiseFitResult::variant, "the structural variant kept, e.g. 'model=ca' (empty: none offered)")
      .def_property_readonly("variants", [](const NoiseFitResult& r) {
            py::list l;
            for (const auto& v : r.variants)
              l.append(py::make_tuple(v.variant, v.objective_before, v.objective_after, v.objective_holdout));
            return l;
          }, "every structural variant fitted: (variant, objective before, after, on the held-out rows "
             "(NaN unless select_holdout > 0))")
      .def_readonly("forecast_variant", &NoiseFitResult::forecast_variant,
                    "the forecast variant kept, e.g. 'hold_blend_frames=1' (empty: the structure's own forecast)")
      .def_property_readonly("forecast_variants", [](const NoiseFitResult& r) {
            py::list l;
            for (const auto& v : r.forecast_variants) l.append(py::make_tuple(v.variant, v.objective_after));
            return l;
          }, "every forecast variant compared after the fit (prediction objective): (variant, h-step RMSE px)")
      .def_readonly("rmse_own_forecast_px", &NoiseFitResult::rmse_own_forecast_px,
                    "h-step RMSE of the structure's own forecast at the fitted noise (NaN: no variant compared)")
      .def_readonly("starts", &NoiseFitResult::starts)
      .def_readonly("best_start", &NoiseFitResult::best_start)
      .def("__repr__", [](const NoiseFitResult& r) {
        return "<predvs.NoiseFitResult " + r.predictor + ": " + std::to_string(r.values.size()) + " values, " +
               std::to_string(r.innovations) + " innovations, " + std::to_string(r.iterations) + " iterations>";
      });

  m.def("fit_parameters", [](const std::string& name) { return fitParameters(name); }, py::arg("name"),
        "The keys fit_noise fits for `name`, with bounds and defaults (ValueError for hold or an unknown name).");
  m.def(
      "fit_noise",
      [](const std::string& name, const py::object& t, const py::object& z, const py::object& params,
         int burn_in_frames, int max_iterations, const std::string& objective, double horizon_s, int starts,
         double select_holdout) {
        if (burn_in_frames < 0) throw std::invalid_argument("burn_in_frames: expected an integer >= 0");
        if (max_iterations < 1) throw std::invalid_argument("max_iterations: expected an integer >= 1");
        if (!(horizon_s >= 0.0)) throw std::invalid_argument("horizon_s: expected a number >= 0");
        if (starts < 1) throw std::invalid_argument("starts: expected an integer >= 1");
        if (!validSelectHoldout(select_holdout))
          throw std::invalid_argument("select_holdout: expected a fraction in [0, 0.9]");
        const Params base = checkedParams(name, params);
        fitParameters(name);        // unknown predictor, or nothing to fit (hold): its message
        makePredictor(name, 2, base);  // an unknown or out-of-range key: its message, as fit-noise --param
        const FitTrack track = fitTrackOf(t, z);
        NoiseFitOptions opt;
        opt.burn_in_frames = burn_in_frames;
        opt.max_iterations = max_iterations;
        opt.objective = parseFitObjective(objective);
        opt.horizon_s = horizon_s;
        opt.starts = starts;
        opt.select_holdout = select_holdout;
        py::gil_scoped_release release;
        return fitNoise(name, base, track, opt);
      },
      py::arg("name"), py::arg("t"), py::arg("z"), py::arg("params") = py::none(), py::arg("burn_in_frames") = 10,
      py::arg("max_iterations") = 200, py::arg("objective") = "likelihood", py::arg("horizon_s") = 0.0,
      py::arg("starts") = 1, py::arg("select_holdout") = NoiseFitOptions{}.select_holdout,
      "Fits the noise keys of `name` on the track t (frames,), z (frames, channels), as `predvs fit-noise`: "
      "objective 'likelihood' (maximum innovation likelihood) or 'prediction' (least h-step prediction "
      "error against the track's later measurements, h = horizon_s; r held). params: starting / fixed values. select_holdout: as fit-noise --select-holdout.");
  m.def(
      "log_likelihood",
      [](const std::string& name, const py::object& t, const py::object& z, const py::object& params,
         int burn_in_frames) {
        if (burn_in_frames < 0) throw std::invalid_argument("burn_in_frames: expected an integer >= 0");
        const Params p = checkedParams(name, params);
        makePredictor(name, 2, p);  // an unknown predictor or key: its message
        const FitTrack track = fitTrackOf(t, z);
        int n = 0;
        const double ll = innovationLogLikelihood(name, p, track, burn_in_frames, &n);
        return py::make_tuple(ll, n);
      },
      py::arg("name"), py::arg("t"), py::arg("z"), py::arg("params") = py::none(), py::arg("burn_in_frames") = 10,
      "(log L, number of innovations) of `name` with params over the track (rows >= burn_in_frames).");

  m.def(
      "read_params", [](const std::string& path) { return entriesToList(readParamFile(path)); }, py::arg("path"),
      "Reads a parameter file: a list of {'name': PREDICTOR, 'params': {KEY: value}}. ValueError naming the "
      "file (and line) on any defect, a missing file included.");
  m.def(
      "params_file_text",
      [](const py::iterable& entries, const std::vector<std::string>& comment) {
        return paramFileText(entriesFromList(entries), comment);
      },
      py::arg("entries"), py::arg("comment") = std::vector<std::string>{},
      "The YAML text of a parameter file for entries [{'name': ..., 'params': {...}}], comment lines first.");
}
