// The Python module: `import memloop`. Options through the parameter registry, a Detector that
// takes numpy images as cv2 gives them, results with the C++ Result's fields; memloop errors
// become Python exceptions carrying the same messages.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/map_info.h"
#include "memloop/options.h"
#include "memloop/params.h"
#include "memloop/realtime.h"
#include "memloop/result.h"

namespace py = pybind11;

namespace {

using memloop::Options;
using memloop::Parameter;

const Parameter& Find(const std::string& name) {
  const Parameter* parameter = memloop::FindParameter(name);
  if (parameter == nullptr) {
    throw memloop::ParameterError(name,
                                  "Unknown parameter '" + name + "' (see memloop.parameters())");
  }
  return *parameter;
}

// A value as Python sees it: bool, int, float or str, by the parameter's type.
py::object Value(const Parameter& parameter, const Options& options) {
  const std::string text = parameter.Get(options);
  if (parameter.flag) return py::bool_(text == "true");
  if (parameter.TypeName() == "int") return py::int_(std::stoll(text));
  if (parameter.TypeName() == "double") return py::float_(std::stod(text));
  return py::str(text);
}

void Assign(Options& options, const std::string& name, const py::handle& value) {
  const Parameter& parameter = Find(name);
  std::string text;
  if (py::isinstance<py::bool_>(value)) {
    text = value.cast<bool>() ? "true" : "false";
  } else if (py::isinstance<py::float_>(value)) {
    text = py::str(py::repr(value)).cast<std::string>();  // shortest round trip
  } else {
    text = py::str(value).cast<std::string>();
  }
  parameter.Set(options, text);
}

Options OptionsFrom(const py::dict& values, const std::string& preset) {
  Options options = memloop::Preset(preset);
  for (const auto& [key, value] : values) Assign(options, py::str(key).cast<std::string>(), value);
  return options;
}

// A numpy image as OpenCV sees it, without a copy: uint8, 2-D (grey) or H x W x 3 (BGR).
cv::Mat ImageOf(const py::array& array) {
  if (!py::isinstance<py::array_t<uint8_t>>(array)) {
    throw memloop::InputError("image", "must be a uint8 numpy array (as cv2.imread gives)");
  }
  const py::array_t<uint8_t, py::array::c_style | py::array::forcecast> image(array);
  if (image.ndim() == 2) {
    const cv::Mat view(static_cast<int>(image.shape(0)), static_cast<int>(image.shape(1)), CV_8UC1,
                       const_cast<uint8_t*>(image.data()));
    // A strided array was copied into `image`, which dies here: keep a copy of that one.
    return image.data() == array.data() ? view : view.clone();
  }
  if (image.ndim() == 3 && (image.shape(2) == 3 || image.shape(2) == 1)) {
    return cv::Mat(static_cast<int>(image.shape(0)), static_cast<int>(image.shape(1)),
                   CV_8UC(static_cast<int>(image.shape(2))), const_cast<uint8_t*>(image.data()))
        .clone();
  }
  throw memloop::InputError("image", "must be H x W (grey) or H x W x 3 (BGR)");
}

// A depth map registered to the image: uint16 millimetres or float32 metres, H x W; empty for
// None.
cv::Mat DepthOf(const std::optional<py::array>& array) {
  if (!array) return {};
  const auto as_mat = [](const auto& depth, int type) {
    if (depth.ndim() != 2) throw memloop::InputError("depth", "must be H x W, one channel");
    return cv::Mat(static_cast<int>(depth.shape(0)), static_cast<int>(depth.shape(1)), type,
                   const_cast<void*>(static_cast<const void*>(depth.data())))
        .clone();
  };
  if (py::isinstance<py::array_t<uint16_t>>(*array)) {
    return as_mat(py::array_t<uint16_t, py::array::c_style | py::array::forcecast>(*array),
                  CV_16UC1);
  }
  if (py::isinstance<py::array_t<float>>(*array)) {
    return as_mat(py::array_t<float, py::array::c_style | py::array::forcecast>(*array), CV_32FC1);
  }
  throw memloop::InputError("depth",
                            "must be a uint16 (millimetres) or float32 (metres) numpy array");
}

memloop::MapMode ModeOf(bool resume, bool new_session) {
  if (resume && new_session) {
    throw memloop::ParameterError("new_session",
                                  "resume=True goes on with the map's last session, "
                                  "new_session=True starts another: give one");
  }
  return resume        ? memloop::MapMode::kResume
         : new_session ? memloop::MapMode::kNewSession
                       : memloop::MapMode::kNew;
}

std::optional<double> Stamp(double timestamp) {
  if (!memloop::HasTimestamp(timestamp)) return std::nullopt;
  return timestamp;
}

class PyDetector {
 public:
  PyDetector(const Options& options, const std::string& path, bool resume, bool new_session)
      : detector_(std::make_unique<memloop::Detector>(options, path, ModeOf(resume, new_session))) {
  }

  memloop::Result Process(const py::array& image, int index, const std::string& name,
                          std::optional<double> timestamp, const std::optional<py::array>& depth) {
    const cv::Mat mat = ImageOf(image);  // `image` outlives the call: no copy needed
    const cv::Mat depth_map = DepthOf(depth);
    memloop::Detector& detector = Live();
    memloop::ImageInfo info;
    info.index = index;
    info.name = name;
    info.timestamp = timestamp.value_or(memloop::kNoTimestamp);
    py::gil_scoped_release release;  // other Python threads run during the iteration
    return detector.Process(mat, depth_map, info);
  }
  void Close() {
    if (detector_) detector_->Close();
    detector_.reset();
  }
  void CloseAtLastCheckpoint() {
    if (detector_) detector_->CloseAtLastCheckpoint();
    detector_.reset();
  }
  memloop::Detector& Live() {
    if (!detector_) throw memloop::Error("the detector is closed");
    return *detector_;
  }

 private:
  std::unique_ptr<memloop::Detector> detector_;
};

}  // namespace

PYBIND11_MODULE(memloop, m) {
  m.doc() = "memloop: real-time appearance-based loop closure detection (Labbe & Michaud 2011)";

  static py::exception<memloop::Error> error(m, "Error");
  static py::exception<memloop::ParameterError> parameter_error(m, "ParameterError", error.ptr());
  static py::exception<memloop::InputError> input_error(m, "InputError", error.ptr());
  static py::exception<memloop::DatabaseError> database_error(m, "DatabaseError",
                                                              input_error.ptr());
  py::register_exception_translator([](std::exception_ptr pointer) {
    try {
      if (pointer) std::rethrow_exception(pointer);
    } catch (const memloop::DatabaseError& e) {
      database_error(e.what());
    } catch (const memloop::InputError& e) {
      input_error(e.what());
    } catch (const memloop::ParameterError& e) {
      parameter_error(e.what());
    } catch (const memloop::Error& e) {
      error(e.what());
    }
  });

  py::class_<Options>(m, "Options", "Parameters by registry name: options['memory.stm_size']")
      .def(py::init(&OptionsFrom), py::arg("values") = py::dict(), py::arg("preset") = "default",
           "The preset's values ('default', 'paper2011', 'hand-held', 'day-night' or 'verified') "
           "with `values` "
           "applied")
      .def("__getitem__", [](const Options& o, const std::string& k) { return Value(Find(k), o); })
      .def("__setitem__",
           [](Options& o, const std::string& k, const py::object& v) { Assign(o, k, v); })
      .def("to_dict", [](const Options& o) {
        py::dict values;
        for (const Parameter& p : memloop::Parameters()) values[py::str(p.key)] = Value(p, o);
        return values;
      });

  py::class_<memloop::StageTimes>(m, "StageTimes")
      .def_readonly("signature_ms", &memloop::StageTimes::signature_ms)
      .def_readonly("rehearsal_ms", &memloop::StageTimes::rehearsal_ms)
      .def_readonly("likelihood_ms", &memloop::StageTimes::likelihood_ms)
      .def_readonly("filter_ms", &memloop::StageTimes::filter_ms)
      .def_readonly("selection_ms", &memloop::StageTimes::selection_ms)
      .def_readonly("retrieval_ms", &memloop::StageTimes::retrieval_ms)
      .def_readonly("transfer_ms", &memloop::StageTimes::transfer_ms)
      .def_readonly("checkpoint_ms", &memloop::StageTimes::checkpoint_ms)
      .def_readonly("ltm_wait_ms", &memloop::StageTimes::ltm_wait_ms)
      .def_readonly("cpu_ms", &memloop::StageTimes::cpu_ms)
      .def_readonly("ltm_read_ms", &memloop::StageTimes::ltm_read_ms)
      .def_readonly("total_ms", &memloop::StageTimes::total_ms);

  using memloop::LoopGeometry;
  py::class_<LoopGeometry>(m, "LoopGeometry")
      .def_readonly("query_view", &LoopGeometry::query_view)
      .def_readonly("match_view", &LoopGeometry::match_view)
      .def_readonly("correspondences", &LoopGeometry::correspondences)
      .def_property_readonly(
          "inliers",
          [](const LoopGeometry& g) {
            py::list pairs;
            for (const memloop::PointPair& p : g.inliers) {
              pairs.append(py::make_tuple(p.query_x, p.query_y, p.match_x, p.match_y));
            }
            return pairs;
          })
      .def_readonly("has_pose", &LoopGeometry::has_pose)
      .def_readonly("pose_problem", &LoopGeometry::pose_problem)
      .def_readonly("rotation", &LoopGeometry::rotation)
      .def_readonly("quaternion", &LoopGeometry::quaternion)
      .def_readonly("translation", &LoopGeometry::translation)
      .def_readonly("translation_known", &LoopGeometry::translation_known)
      .def_readonly("translation_metric", &LoopGeometry::translation_metric)
      .def_readonly("pose_inliers", &LoopGeometry::pose_inliers);

  using memloop::Result;
  py::class_<Result>(m, "Result")
      .def_readonly("image_index", &Result::image_index)
      .def_property_readonly("timestamp", [](const Result& r) { return Stamp(r.timestamp); })
      .def_readonly("session", &Result::session)
      .def_readonly("location_id", &Result::location_id)
      .def_readonly("rehearsal_merged_id", &Result::rehearsal_merged_id)
      .def_readonly("feature_count", &Result::feature_count)
      .def_readonly("features_skipped", &Result::features_skipped)
      .def_readonly("time_decided", &Result::time_decided)
      .def_readonly("word_count", &Result::word_count)
      .def_readonly("hypothesis_id", &Result::hypothesis_id)
      .def_readonly("hypothesis_value", &Result::hypothesis_value)
      .def_readonly("hypothesis_images", &Result::hypothesis_images)
      .def_readonly("hypothesis_eligible", &Result::hypothesis_eligible)
      .def_readonly("hypothesis_inliers", &Result::hypothesis_inliers)
      .def_readonly("virtual_place_probability", &Result::virtual_place_probability)
      .def_readonly("loop_closure_id", &Result::loop_closure_id)
      .def_readonly("loop_closure_images", &Result::loop_closure_images)
      .def_readonly("loop_closure_geometry", &Result::loop_closure_geometry)
      .def_readonly("retrieved_ids", &Result::retrieved_ids)
      .def_readonly("retrievals_deferred", &Result::retrievals_deferred)
      .def_readonly("retrievals_unread", &Result::retrievals_unread)
      .def_readonly("appearance_match_id", &Result::appearance_match_id)
      .def_readonly("appearance_match_z", &Result::appearance_match_z)
      .def_readonly("transferred_ids", &Result::transferred_ids)
      .def_readonly("stm_size", &Result::stm_size)
      .def_readonly("wm_size", &Result::wm_size)
      .def_readonly("ltm_size", &Result::ltm_size)
      .def_readonly("dictionary_size", &Result::dictionary_size)
      .def_readonly("times", &Result::times)
      .def_property_readonly("has_loop_closure", &Result::HasLoopClosure)
      .def("brief", &Result::Brief)
      .def("__repr__", &Result::Brief);

  py::class_<PyDetector>(m, "Detector")
      .def(py::init<const Options&, const std::string&, bool, bool>(), py::arg("options"),
           py::arg("db_path"), py::arg("resume") = false, py::arg("new_session") = false,
           "A new map at db_path (or, resume=True, an existing one from its last checkpoint; "
           "new_session=True, an existing one given a new session; with "
           "options['memory.localization'] = True, an existing map localized against, "
           "read-only)")
      .def("process", &PyDetector::Process, py::arg("image"), py::arg("index") = -1,
           py::arg("name") = "", py::arg("timestamp") = py::none(), py::arg("depth") = py::none(),
           "One image (numpy uint8, grey or BGR as cv2 gives), with the name and time stamp "
           "(seconds) the map records, and its depth map registered to it (uint16 millimetres "
           "or float32 metres; with camera.fx..cy, loop closures' translations are then in "
           "metres); returns a Result")
      .def("close", &PyDetector::Close, "Stores STM and WM too: the map is then complete")
      .def("close_at_last_checkpoint", &PyDetector::CloseAtLastCheckpoint,
           "Closes as a crash would: the map stays at the checkpoint written by the last "
           "process() call, i.e. without the last image (for a caller that could not store its "
           "result)")
      .def_property_readonly("last_image", [](PyDetector& d) { return d.Live().last_image(); })
      .def_property_readonly("session", [](PyDetector& d) { return d.Live().session(); })
      .def_property_readonly("session_first_image",
                             [](PyDetector& d) { return d.Live().session_first_image(); })
      .def("__enter__", [](PyDetector& d) -> PyDetector& { return d; })
      .def("__exit__", [](PyDetector& d, py::args) { d.Close(); });

  m.def(
      "parameters",
      [] {
        const Options defaults;
        py::list rows;
        for (const Parameter& p : memloop::Parameters()) {
          py::dict row;
          row["name"] = p.key;
          row["default"] = Value(p, defaults);
          row["type"] = p.TypeName();
          row["unit"] = p.unit;
          row["range"] = p.RangeText();
          row["description"] = p.description;
          rows.append(row);
        }
        return rows;
      },
      "Every parameter of the registry: name, default, type, unit, range, description");
  m.def("set_realtime_priority", &memloop::SetThisThreadsRealTimePriority, py::arg("priority"),
        "Runs the calling thread, and the detector threads it starts after, under SCHED_FIFO at "
        "`priority` (1-99; needs root, CAP_SYS_NICE or ulimit -r): call before making the "
        "Detector. Raises memloop.Error when refused");
  m.def("realtime_priority", &memloop::ThisThreadsRealTimePriority,
        "The calling thread's real-time priority (0: the usual scheduling)");
  m.def("read_map_options", &memloop::ReadMapOptions, py::arg("db_path"),
        "The options a map was made with (for resume=True)");
  m.def(
      "read_map_images",
      [](const std::string& path) {
        py::list rows;
        for (const memloop::MapImage& image : memloop::ReadMapImages(path)) {
          py::dict row;
          row["index"] = image.index;
          row["session"] = image.session;
          row["name"] = image.name;
          row["timestamp"] = Stamp(image.timestamp);
          rows.append(row);
        }
        return rows;
      },
      py::arg("db_path"), "Every image the map records: index, session, name, timestamp");
}
