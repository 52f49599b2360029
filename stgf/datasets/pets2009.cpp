// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/pets2009.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "stgf/datasets/xml_file.hpp"
#include "stgf/io/input_error.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

// The parsed annotation file and the line numbers of its elements.
class AnnotationFile : public XmlFile {
 public:
  explicit AnnotationFile(const std::string& path) : XmlFile(path, "dataset") {}

  // A frame's number: a whole number ≥ 0.
  int frame_number(const pugi::xml_node& frame) const {
    const pugi::xml_attribute attribute = frame.attribute("number");
    if (!attribute) fail(frame, "<frame> has no attribute number");
    const std::optional<double> value = parse_attribute_number(attribute.value());
    if (!value || *value < 0.0 || *value != std::floor(*value) || *value > 1e9) {
      fail(frame, fmt::format("<frame> number=\"{}\" is not a whole number >= 0", attribute.value()));
    }
    return static_cast<int>(*value);
  }

  double size(const pugi::xml_node& element, const char* name) const {
    const double value = number(element, name);
    if (value < 0.0) {
      fail(element,
           fmt::format("<{}> attribute {} must not be negative (got {})", element.name(), name, value));
    }
    return value;
  }

  // The frames in file order, each number checked and unique.
  std::vector<std::pair<int, pugi::xml_node>> frames() const {
    std::vector<std::pair<int, pugi::xml_node>> frames;
    std::set<int> seen;
    for (const pugi::xml_node& frame : top().children("frame")) {
      const int number = frame_number(frame);
      if (!seen.insert(number).second) fail(frame, fmt::format("frame {} appears a second time", number));
      frames.emplace_back(number, frame);
    }
    return frames;
  }
};

}  // namespace

CvmlAnnotations read_cvml_annotations(const std::string& path) {
  const AnnotationFile file(path);
  CvmlAnnotations annotations;
  for (const auto& [number, frame] : file.frames()) {
    annotations.frames.push_back(number);
    std::set<std::string> ids_in_frame;
    // Objects sit in <objectlist>; a frame without one has nobody annotated.
    for (const pugi::xml_node& object : frame.child("objectlist").children("object")) {
      const std::string id = object.attribute("id").value();
      if (id.empty()) file.fail(object, "<object> has no id");
      if (!ids_in_frame.insert(id).second) {
        file.fail(object, fmt::format("object id {} appears twice in frame {}", id, number));
      }
      const pugi::xml_node box = object.child("box");
      if (!box) file.fail(object, fmt::format("object {} in frame {} has no <box>", id, number));
      AnnotatedBox annotated;
      annotated.frame = number;
      annotated.object = "p" + id;
      annotated.height_px = file.size(box, "h");
      annotated.width_px = file.size(box, "w");
      annotated.centre_u_px = file.number(box, "xc");
      annotated.centre_v_px = file.number(box, "yc");
      annotated.line = file.line(object);
      annotations.boxes.push_back(std::move(annotated));
    }
  }
  std::sort(annotations.frames.begin(), annotations.frames.end());
  return annotations;
}

Recording ground_recording(std::string name, const CvmlAnnotations& annotations, const TsaiCamera& camera,
                           double rate_hz, const std::string& annotation_path) {
  Recording recording;
  recording.name = std::move(name);
  recording.rate_hz = rate_hz;
  for (const int frame : annotations.frames) recording.frames[frame];
  for (const AnnotatedBox& box : annotations.boxes) {
    const std::optional<Vector3d> ground = camera.back_project_to_ground(box.foot_pixel(), 0.0);
    if (!ground) {
      throw InputError(
          annotation_path, box.line,
          fmt::format("the foot pixel ({}, {}) of {} in frame {} does not look down on the ground "
                      "through camera {}",
                      box.foot_pixel().x(), box.foot_pixel().y(), box.object, box.frame, camera.name()));
    }
    recording.frames[box.frame][box.object] = *ground;
  }
  return recording;
}

std::string pets2009_annotation_path(const std::string& source_directory) {
  return (std::filesystem::path(source_directory) / "PETS2009-S2L1.xml").string();
}

std::string pets2009_calibration_path(const std::string& source_directory, int view) {
  return (std::filesystem::path(source_directory) / "calibration" / fmt::format("View_{:03d}.xml", view))
      .string();
}

Recording read_pets2009_recording(const std::string& source_directory) {
  const std::string annotation_path = pets2009_annotation_path(source_directory);
  const TsaiCamera view1 = read_tsai_camera(pets2009_calibration_path(source_directory, 1));
  return ground_recording("PETS2009-S2L1", read_cvml_annotations(annotation_path), view1,
                          kPets2009FrameRateHz, annotation_path);
}

}  // namespace stgf
