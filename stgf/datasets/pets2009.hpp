// SPDX-License-Identifier: Apache-2.0
#pragma once
// PETS 2009 S2.L1 ground truth as world trajectories (data/README.md §2; the mpl benchmark's source).
//
// The annotation file (Anton Milan's, CVML layout) holds boxes in view-1 image pixels:
//   <dataset>
//     <frame number="N">
//       <objectlist>
//         <object id="K"><box h=".." w=".." xc=".." yc=".."/></object>  …
//       </objectlist>
//     </frame>  …
//   </dataset>
// (xc, yc) is the box centre and (w, h) its size, in pixels of View_001 (768×576). The person stands
// on the ground at the box's bottom centre, the foot pixel (xc, yc + h/2).
//
// World trajectory: each foot pixel is back-projected through the View_001 Tsai calibration onto the
// ground plane z = 0 (TsaiCamera::back_project_to_ground), giving (x, y, 0) in metres in the PETS
// world frame. The sequence runs at 7 frames per second, so frame f is at t = f / 7 s. Object ids are
// "p" followed by the file's id ("p9"). Every frame element of the file is a frame of the recording,
// also when nobody is annotated in it.

#include <string>
#include <vector>

#include "stgf/datasets/recording.hpp"
#include "stgf/datasets/tsai_camera.hpp"

namespace stgf {

inline constexpr double kPets2009FrameRateHz = 7.0;

// One annotated box.
struct AnnotatedBox {
  int frame = 0;
  std::string object;        // "p" + the file's id
  double centre_u_px = 0.0;  // xc
  double centre_v_px = 0.0;  // yc
  double width_px = 0.0;     // w
  double height_px = 0.0;    // h
  int line = 0;              // line of the <object> element in the file (for messages)

  // (xc, yc + h/2): where the person touches the ground, in view-1 pixels.
  Vector2d foot_pixel() const { return Vector2d(centre_u_px, centre_v_px + 0.5 * height_px); }
};

// What a CVML annotation file holds.
struct CvmlAnnotations {
  std::vector<int> frames;  // the numbers of all <frame> elements (also those without objects), ascending
  std::vector<AnnotatedBox> boxes;  // every box, in file order
};

// Reads a CVML annotation file. Throws InputError naming `path` and the line when the file cannot be
// read or is not well-formed XML, when there is no <dataset> element, a frame number is missing, not
// a whole number >= 0 or repeated, an object has no id or no <box>, an id appears twice in one frame,
// or a box attribute (h, w, xc, yc) is missing, not a finite number, or (h, w) negative.
CvmlAnnotations read_cvml_annotations(const std::string& path);

// The recording of world foot points: every box's foot pixel back-projected through `camera` onto
// z = 0, at `rate_hz`; every annotated frame exists in the recording, with or without people.
// Throws InputError(annotation_path, the box's line) when a foot pixel's line of sight does not reach
// the ground in front of the camera.
Recording ground_recording(std::string name, const CvmlAnnotations& annotations, const TsaiCamera& camera,
                           double rate_hz, const std::string& annotation_path);

// The paths of the PETS 2009 S2.L1 files in a source folder laid out as data/pets2009_s2l1:
//   DIR/PETS2009-S2L1.xml and DIR/calibration/View_00N.xml (N = 1 … 8).
std::string pets2009_annotation_path(const std::string& source_directory);
std::string pets2009_calibration_path(const std::string& source_directory, int view);

// The whole recording from a source folder: read_cvml_annotations(annotation) through
// read_tsai_camera(View_001), named "PETS2009-S2L1", at kPets2009FrameRateHz.
Recording read_pets2009_recording(const std::string& source_directory);

}  // namespace stgf
