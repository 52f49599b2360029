// SPDX-License-Identifier: Apache-2.0
// The Python module stgf._stgf (pybind11 + NumPy); python/stgf/__init__.py is its public face.
//
// Arrays cross the boundary as float64, C order: n measurements are
//   time (n,), z (n, 3), R (n, 3, 3), arrival (n,) optional, sensor_position (n, 3) optional,
// with scene, view and object as sequences of n strings (or one string for every row). Estimates come
// back as mean (n, 3) and covariance (n, 3, 3), one per measurement in the given order.
// C++ errors keep their messages: stgf::InputError → stgf.InputError (a ValueError, "FILE:LINE: …"),
// LateMeasurementError → stgf.LateMeasurementError, std::invalid_argument → ValueError, other
// std::exception → RuntimeError. The GIL is released while the filter computes.

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "stgf/core/metrics.hpp"
#include "stgf/core/motion_predictor.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/evaluation.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/method_config_file.hpp"
#include "stgf/io/truth_file.hpp"
#include "stgf/model/general_model.hpp"
#include "stgf/model/named_methods.hpp"
#include "stgf/model/trained_motion_model.hpp"
#include "stgf/methods/spatiotemporal_graph_filter.hpp"
#include "stgf/version.hpp"

namespace py = pybind11;

namespace stgf::python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// ── Arrays ↔ records ─────────────────────────────────────────────────────────────────────────────

void check_shape(const Array& array, const char* name, std::vector<py::ssize_t> shape) {
  bool ok = array.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t k = 0; ok && k < shape.size(); ++k) ok = array.shape(static_cast<py::ssize_t>(k)) == shape[k];
  if (ok) return;
  const auto listed = [](const auto& sizes) {
    std::string text = "(";
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      if (k > 0) text += ", ";
      text += std::to_string(sizes[k]);
    }
    return text + ")";
  };
  const std::vector<py::ssize_t> got(array.shape(), array.shape() + array.ndim());
  throw std::invalid_argument(std::string(name) + " has shape " + listed(got) + " where " + listed(shape) +
                              " was expected");
}

// n strings from a str (repeated) or a sequence of n str.
std::vector<std::string> strings(const py::object& value, std::size_t n, const char* name) {
  if (py::isinstance<py::str>(value)) return std::vector<std::string>(n, value.cast<std::string>());
  std::vector<std::string> out;
  try {
    out = value.cast<std::vector<std::string>>();
  } catch (const py::cast_error&) {
    throw std::invalid_argument(std::string(name) + " must be a str or a sequence of str");
  }
  if (out.size() != n) {
    throw std::invalid_argument(std::string(name) + " has " + std::to_string(out.size()) + " entries for " +
                                std::to_string(n) + " measurements");
  }
  return out;
}

Vector3d row3(const Array& a, py::ssize_t i) {
  const auto v = a.unchecked<2>();
  return Vector3d(v(i, 0), v(i, 1), v(i, 2));
}

Matrix3d matrix3(const Array& a, py::ssize_t i) {
  const auto v = a.unchecked<3>();
  Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = v(i, r, c);
  }
  return m;
}

// Row i of (mean, covariance) as a checked Gaussian; std::invalid_argument prefixed with `where`.
Gaussian3 gaussian(const Array& mean, const Array& covariance, py::ssize_t i, const std::string& where) {
  try {
    return Gaussian3::from_covariance(row3(mean, i), matrix3(covariance, i));
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(where + error.what());
  }
}

std::vector<Measurement> measurements_from_arrays(const py::object& scene, const Array& time, const py::object& view,
                                                  const py::object& object, const Array& z, const Array& R,
                                                  const std::optional<Array>& arrival,
                                                  const std::optional<Array>& sensor_position) {
  if (time.ndim() != 1) throw std::invalid_argument("time must be one-dimensional (n,)");
  const py::ssize_t n = time.shape(0);
  check_shape(z, "z", {n, 3});
  check_shape(R, "R", {n, 3, 3});
  if (arrival) check_shape(*arrival, "arrival", {n});
  if (sensor_position) check_shape(*sensor_position, "sensor_position", {n, 3});
  const auto count = static_cast<std::size_t>(n);
  const std::vector<std::string> scenes = strings(scene, count, "scene");
  const std::vector<std::string> views = strings(view, count, "view");
  const std::vector<std::string> objects = strings(object, count, "object");
  const auto t = time.unchecked<1>();
  std::vector<Measurement> rows;
  rows.reserve(count);
  for (py::ssize_t i = 0; i < n; ++i) {
    const std::string where = "measurement " + std::to_string(i) + ": ";
    if (!std::isfinite(t(i))) throw std::invalid_argument(where + "time is not finite");
    const auto k = static_cast<std::size_t>(i);
    rows.push_back(Measurement{scenes[k], t(i), views[k], objects[k], gaussian(z, R, i, where), std::nullopt, std::nullopt});
    if (arrival) rows.back().arrival = arrival->at(i);
    if (sensor_position) {
      const Vector3d sensor = row3(*sensor_position, i);
      if (!sensor.allFinite()) throw std::invalid_argument(where + "sensor_position is not finite");
      rows.back().sensor_position = sensor;
    }
  }
  return rows;
}

// n Gaussians as out[mean_key] (n, 3) and out[covariance_key] (n, 3, 3); `at(i)` gives the i-th.
template <typename GaussianAt>
void put_gaussians(py::dict& out, py::ssize_t n, GaussianAt at, const char* mean_key, const char* covariance_key) {
  Array mean({n, py::ssize_t{3}});
  Array covariance({n, py::ssize_t{3}, py::ssize_t{3}});
  auto m = mean.mutable_unchecked<2>();
  auto c = covariance.mutable_unchecked<3>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const Gaussian3& e = at(static_cast<std::size_t>(i));
    for (int r = 0; r < 3; ++r) {
      m(i, r) = e.mean()(r);
      for (int k = 0; k < 3; ++k) c(i, r, k) = e.covariance()(r, k);
    }
  }
  out[mean_key] = mean;
  out[covariance_key] = covariance;
}

py::dict estimates_to_dict(const std::vector<Gaussian3>& estimates) {
  py::dict out;
  put_gaussians(out, static_cast<py::ssize_t>(estimates.size()),
                [&](std::size_t i) -> const Gaussian3& { return estimates[i]; }, "mean", "covariance");
  return out;
}

py::object json_to_python(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

MethodConfig config_from(const std::optional<std::string>& path) {
  return path ? read_method_config(*path) : MethodConfig{};
}

// ── Model ────────────────────────────────────────────────────────────────────────────────────────

struct Model {
  std::shared_ptr<const TrainedMotionModel> model;
  std::string path;
};

Model load_model(const std::string& path) { return Model{std::make_shared<const TrainedMotionModel>(TrainedMotionModel::load(path)), path}; }
// The general model shipped with stgf (stgf/model/general_model.hpp).
Model shipped_general_model() { return Model{std::make_shared<const TrainedMotionModel>(general_model()), kGeneralModelName}; }

// ── Streaming filter ─────────────────────────────────────────────────────────────────────────────

// One scene's streaming filter (methods/spatiotemporal_graph_filter.hpp) that owns its predictor.
class Filter {
 public:
  Filter(const py::object& model, const std::optional<std::string>& config, double process_noise, double typical_speed) {
    const MethodConfig settings = config_from(config);
    nlohmann::json metadata = nlohmann::json::object();
    std::string model_path = "(no model)";
    if (model.is_none()) {
      predictor_ = std::make_shared<ConstantVelocityPredictor>(process_noise, typical_speed);
    } else {
      const Model loaded = py::isinstance<py::str>(model) ? load_model(model.cast<std::string>()) : model.cast<Model>();
      metadata = loaded.model->metadata();
      model_path = loaded.path;
      predictor_ = loaded.model;
    }
    filter_ = std::make_unique<SpatiotemporalGraphFilter>(*predictor_,
                                                          filter_options_for(settings.ours, metadata, model_path));
  }

  py::dict fuse(const Array& time, const py::object& view, const py::object& object, const Array& z, const Array& R,
                const std::optional<Array>& sensor_position) {
    const std::vector<Measurement> rows =
        measurements_from_arrays(py::str("scene"), time, view, object, z, R, {}, sensor_position);
    std::vector<Gaussian3> estimates;
    {
      py::gil_scoped_release release;
      estimates = filter_->fuse(rows);
    }
    return estimates_to_dict(estimates);
  }

  std::pair<double, double> registration_prior_scales() const {
    const RegistrationPriorScales scales = filter_->registration_prior_scales();
    return {scales.translation, scales.noise_ratio};
  }

  py::array registration_offset(const std::string& view) const {
    const OffsetVector offset = filter_->registration_offset(view);
    Array out(py::ssize_t{kOffsetSize});  // (t, δ, ε)
    for (int k = 0; k < kOffsetSize; ++k) out.mutable_at(k) = offset(k);
    return out;
  }

  std::size_t late_measurements() const { return filter_->late_measurements(); }
  std::size_t rewinds() const { return filter_->rewinds(); }
  std::size_t late_rows() const { return filter_->late_rows(); }
  std::size_t refilters() const { return filter_->refilters(); }
  std::size_t restarted_tracks() const { return filter_->restarted_tracks(); }
  // Which motion the tracks follow (design §1.13): "model" or "constant-velocity".
  std::string motion() const { return filter_->motion_choice().constant_velocity() ? "constant-velocity" : "model"; }
  // Per view: what the χ² gate checked and left out, its noise scale, and its measurements the other
  // views outvoted (fused with their noise scaled up: cross_view_weights, on without the gate too;
  // design §1.12).
  py::dict gating() const {
    py::dict views;
    for (const auto& [view, report] : filter_->view_noise_scales().reports()) {
      py::dict entry;
      entry["checked"] = report.checked;
      entry["gated"] = report.gated;
      entry["largest_noise_scale"] = report.largest_scale;
      entry["offset_releases"] = report.offset_releases;
      entry["down_weighted"] = report.down_weighted;
      views[py::str(view)] = entry;
    }
    return views;
  }

 private:
  std::shared_ptr<const MotionPredictor> predictor_;
  std::unique_ptr<SpatiotemporalGraphFilter> filter_;
};

// ── Batch methods, files, metrics ────────────────────────────────────────────────────────────────

py::dict run(const std::string& method, const py::object& scene, const Array& time, const py::object& view,
             const py::object& object, const Array& z, const Array& R, const std::optional<Array>& arrival,
             const std::optional<Array>& sensor_position, const py::object& model,
             const std::optional<std::string>& config) {
  if (std::find(all_method_names().begin(), all_method_names().end(), method) == all_method_names().end()) {
    std::string known;
    for (const std::string& name : all_method_names()) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument("unknown method '" + method + "' (known: " + known + ")");
  }
  const MethodConfig settings = config_from(config);
  const std::vector<Measurement> rows = measurements_from_arrays(scene, time, view, object, z, R, arrival, sensor_position);
  std::optional<Model> loaded;
  if (is_learned_method(method)) {
    // No model: ours and ours-l get the general model, as `stgf run` without --model (sttp: an error).
    if (model.is_none()) {
      loaded = Model{std::make_shared<const TrainedMotionModel>(load_model_for(method, "")), kGeneralModelName};
    } else {
      loaded = py::isinstance<py::str>(model) ? Model{std::make_shared<const TrainedMotionModel>(load_model_for(method, model.cast<std::string>())),
                                                    model.cast<std::string>()}
                                              : model.cast<Model>();
    }
  }
  MethodRunReport report;
  std::vector<Gaussian3> estimates;
  {
    py::gil_scoped_release release;
    estimates = run_named_method(method, settings, loaded ? loaded->model.get() : nullptr, loaded ? loaded->path : "",
                                 rows, &report);
  }
  py::dict out = estimates_to_dict(estimates);
  py::dict counts;
  counts["restarted_tracks"] = report.restarted_tracks;
  counts["late_rows"] = report.late_rows;
  counts["rewinds"] = report.rewinds;
  counts["refilters"] = report.gating.refilters;
  counts["late_measurements"] = report.late_measurements;
  counts["registration_missing"] = report.registration_missing;
  counts["constant_velocity_scenes"] = report.motion_choice.constant_velocity_scenes;
  out["report"] = counts;
  return out;
}

py::dict read_measurements_file(const std::string& path) {
  const MeasurementFile file = read_measurements(path);
  const auto n = static_cast<py::ssize_t>(file.rows.size());
  std::vector<std::string> scene, view, object;
  Array time(n);
  auto t = time.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const Measurement& row = file.rows[static_cast<std::size_t>(i)];
    scene.push_back(row.scene);
    view.push_back(row.view);
    object.push_back(row.object);
    t(i) = row.time;
  }
  py::dict out;
  out["scene"] = scene;
  out["time"] = time;
  out["view"] = view;
  out["object"] = object;
  put_gaussians(out, n, [&](std::size_t i) -> const Gaussian3& { return file.rows[i].position; }, "z", "R");
  out["line"] = file.lines;
  out["arrival"] = py::none();
  out["sensor_position"] = py::none();
  if (file.has_arrival) {
    Array arrival(n);
    for (py::ssize_t i = 0; i < n; ++i) arrival.mutable_at(i) = file.rows[static_cast<std::size_t>(i)].arrival.value_or(t(i));
    out["arrival"] = arrival;
  }
  if (file.has_sensor_positions) {
    Array sensor({n, py::ssize_t{3}});
    for (py::ssize_t i = 0; i < n; ++i) {
      const Vector3d p = file.rows[static_cast<std::size_t>(i)].sensor_position.value_or(Vector3d::Constant(std::nan("")));
      for (int r = 0; r < 3; ++r) sensor.mutable_at(i, r) = p(r);
    }
    out["sensor_position"] = sensor;
  }
  return out;
}

py::dict read_truth_file(const std::string& path) {
  const TruthFile file = read_truth(path);
  const auto n = static_cast<py::ssize_t>(file.rows.size());
  std::vector<std::string> scene, object;
  Array time(n), position({n, py::ssize_t{3}});
  for (py::ssize_t i = 0; i < n; ++i) {
    const TruthPoint& row = file.rows[static_cast<std::size_t>(i)];
    scene.push_back(row.scene);
    object.push_back(row.object);
    time.mutable_at(i) = row.time;
    for (int r = 0; r < 3; ++r) position.mutable_at(i, r) = row.position(r);
  }
  py::dict out;
  out["scene"] = scene;
  out["time"] = time;
  out["object"] = object;
  out["position"] = position;
  out["line"] = file.lines;
  return out;
}

py::dict read_estimates_file(const std::string& path) {
  const EstimateFile file = read_estimates(path);
  std::vector<std::string> scene, view, object;
  Array time(static_cast<py::ssize_t>(file.rows.size()));
  for (std::size_t i = 0; i < file.rows.size(); ++i) {
    const Estimate& row = file.rows[i];
    scene.push_back(row.scene);
    view.push_back(row.view);
    object.push_back(row.object);
    time.mutable_at(static_cast<py::ssize_t>(i)) = row.time;
  }
  py::dict out;
  put_gaussians(out, static_cast<py::ssize_t>(file.rows.size()),
                [&](std::size_t i) -> const Gaussian3& { return file.rows[i].position; }, "mean", "covariance");
  out["scene"] = scene;
  out["time"] = time;
  out["view"] = view;
  out["object"] = object;
  out["method"] = file.methods;
  out["line"] = file.lines;
  return out;
}

void write_estimates_file(const std::string& path, const py::object& scene, const Array& time, const py::object& view,
                          const py::object& object, const Array& mean, const Array& covariance, const std::string& method) {
  if (time.ndim() != 1) throw std::invalid_argument("time must be one-dimensional (n,)");
  const py::ssize_t n = time.shape(0);
  check_shape(mean, "mean", {n, 3});
  check_shape(covariance, "covariance", {n, 3, 3});
  const auto count = static_cast<std::size_t>(n);
  const std::vector<std::string> scenes = strings(scene, count, "scene");
  const std::vector<std::string> views = strings(view, count, "view");
  const std::vector<std::string> objects = strings(object, count, "object");
  std::vector<Estimate> rows;
  rows.reserve(count);
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    rows.push_back(Estimate{scenes[k], time.at(i), views[k], objects[k],
                            gaussian(mean, covariance, i, "estimate " + std::to_string(i) + ": ")});
  }
  write_estimates(path, rows, method);
}

py::dict summary_to_dict(const ErrorSummary& summary) {
  py::dict out;
  out["rows"] = summary.rows;
  out["de"] = summary.displacement_error;
  out["rel_de"] = summary.relative_displacement_error;
  out["nees_mean"] = summary.nees_mean;
  out["nees_in_95"] = summary.nees_share_in_95;
  out["nees_horizontal_mean"] = summary.nees_horizontal_mean;  // x, y: 2 when calibrated
  out["nees_vertical_mean"] = summary.nees_vertical_mean;      // z: 1 when calibrated
  return out;
}

py::dict metrics(const Array& mean, const Array& covariance, const Array& truth, const std::optional<Array>& sensor_position) {
  if (mean.ndim() != 2) throw std::invalid_argument("mean must be (n, 3)");
  const py::ssize_t n = mean.shape(0);
  check_shape(mean, "mean", {n, 3});
  check_shape(covariance, "covariance", {n, 3, 3});
  check_shape(truth, "truth", {n, 3});
  if (sensor_position) check_shape(*sensor_position, "sensor_position", {n, 3});
  ErrorAccumulator accumulator;
  for (py::ssize_t i = 0; i < n; ++i) {
    accumulator.add(gaussian(mean, covariance, i, "estimate " + std::to_string(i) + ": "), row3(truth, i), sensor_position ? std::optional<Vector3d>(row3(*sensor_position, i)) : std::nullopt);
  }
  return summary_to_dict(accumulator.summary());
}

py::list evaluate_files(const std::string& truth, const std::vector<std::string>& estimates,
                        const std::optional<std::string>& measurements, int from_step, double from_time) {
  const TruthFile truth_file = read_truth(truth);
  std::vector<EstimateFile> estimate_files;
  for (const std::string& path : estimates) estimate_files.push_back(read_estimates(path));
  std::optional<MeasurementFile> measurement_file;
  if (measurements) measurement_file = read_measurements(*measurements);
  const Evaluation evaluation = evaluate(truth_file, estimate_files, measurement_file ? &*measurement_file : nullptr,
                                         ScoringStart{from_step, from_time});
  py::list out;
  for (const MethodScore& score : evaluation.methods) {
    py::dict method = summary_to_dict(score.overall);
    method["method"] = score.method;
    method["file"] = score.file;
    py::dict by_views;
    for (const auto& [views, summary] : score.by_views) by_views[py::int_(views)] = summary_to_dict(summary);
    method["by_views"] = by_views;
    py::dict by_variance;  // per axis: each octave [2^k, 2^(k+1)) m² of the stated variance that holds a row
    for (int a = 0; a < 3; ++a) {
      py::list bins;
      for (const VarianceBin& bin : score.by_variance[a]) {
        py::dict entry;
        entry["variance_from"] = bin.variance_from();
        entry["variance_to"] = bin.variance_to();
        entry["rows"] = bin.rows;
        entry["mean_variance"] = bin.mean_variance;
        entry["mean_squared_error"] = bin.mean_squared_error;
        bins.append(entry);
      }
      by_variance[py::str(std::string(1, "xyz"[a]))] = bins;
    }
    method["by_variance"] = by_variance;
    out.append(method);
  }
  return out;
}

}  // namespace
}  // namespace stgf::python

PYBIND11_MODULE(_stgf, m) {
  using namespace stgf::python;
  namespace sp = stgf::python;
  m.doc() = "stgf: multi-view collaborative object localization (the C++ core; see the stgf package)";
  m.attr("__version__") = stgf::kVersion;

  py::register_exception<stgf::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<stgf::LateMeasurementError>(m, "LateMeasurementError", PyExc_ValueError);

  py::class_<Model>(m, "Model", "A motion model Φ loaded from a file written by `stgf train`.")
      .def_property_readonly("path", [](const Model& model) { return model.path; })
      .def_property_readonly("metadata", [](const Model& model) { return json_to_python(model.model->metadata()); })
      .def_property_readonly("history_positions", [](const Model& model) { return model.model->history_positions(); })
      .def_property_readonly("typical_speed", [](const Model& model) { return model.model->typical_speed(); })
      .def_property_readonly("history_spacing", [](const Model& model) { return model.model->history_spacing(); })
      .def_property_readonly("prediction_horizon", [](const Model& model) { return model.model->prediction_horizon(); })
      .def("process_noise", [](const Model& model, double dt) {
        const stgf::Matrix3d q = model.model->process_noise(dt);
        Array out({py::ssize_t{3}, py::ssize_t{3}});
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) out.mutable_at(r, c) = q(r, c);
        }
        return out;
      }, py::arg("dt"), "Q (m²) for a prediction interval of dt seconds.");

  m.def("load_model", &sp::load_model, py::arg("path"));
  m.def("general_model", &sp::shipped_general_model,
        "The general model shipped with stgf (models/README.md): what run() uses for ours and ours-l without a model.");

  py::class_<Filter>(m, "Filter")
      .def(py::init<const py::object&, const std::optional<std::string>&, double, double>(), py::arg("model") = py::none(),
           py::arg("config") = py::none(), py::arg("process_noise") = 0.5, py::arg("typical_speed") = 1.4)
      .def("fuse", &Filter::fuse, py::arg("time"), py::arg("view"), py::arg("object"), py::arg("z"), py::arg("R"),
           py::arg("sensor_position") = py::none())
      .def("registration_offset", &Filter::registration_offset, py::arg("view"))
      .def_property_readonly("registration_prior_scales", &Filter::registration_prior_scales,
                             "(κ_t, κ_n): the registration prior's learned scales on the translation and on the offset in units of the noise (1 until learned)")
      .def_property_readonly("late_measurements", &Filter::late_measurements)
      .def_property_readonly("rewinds", &Filter::rewinds, "times the filter went back for late rows")
      .def_property_readonly("late_rows", &Filter::late_rows,
                             "rows fused in their place in time though a later time had been processed when they came")
      .def_property_readonly("refilters", &Filter::refilters)
      .def_property_readonly("restarted_tracks", &Filter::restarted_tracks)
      .def_property_readonly("motion", &Filter::motion)
      .def_property_readonly("gating", &Filter::gating);

  m.def("run", &sp::run, py::arg("method"), py::arg("scene"), py::arg("time"), py::arg("view"), py::arg("object"),
        py::arg("z"), py::arg("R"), py::arg("arrival") = py::none(), py::arg("sensor_position") = py::none(),
        py::arg("model") = py::none(), py::arg("config") = py::none());
  m.def("method_names", [] { return stgf::all_method_names(); });
  m.def("read_measurements", &read_measurements_file, py::arg("path"));
  m.def("read_truth", &read_truth_file, py::arg("path"));
  m.def("read_estimates", &read_estimates_file, py::arg("path"));
  m.def("write_estimates", &write_estimates_file, py::arg("path"), py::arg("scene"), py::arg("time"), py::arg("view"),
        py::arg("object"), py::arg("mean"), py::arg("covariance"), py::arg("method"));
  m.def("metrics", &metrics, py::arg("mean"), py::arg("covariance"), py::arg("truth"),
        py::arg("sensor_position") = py::none());
  m.def("evaluate", &evaluate_files, py::arg("truth"), py::arg("estimates"), py::arg("measurements") = py::none(),
        py::arg("from_step") = 0, py::arg("from_time") = 0.0);
}
