// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A subject: one person's measurements and what to make of them (the
// thesis's whole job: poke a person at several body locations, fit the tissue
// there, build their body model from those fits and their ultrasound depths,
// and design a support for them).
//
// A subject file (JSON; relative paths resolve against its folder):
//
// {
//   "palpa_subject": 1,
//   "name": "s01",                        // letters, digits, '-', '_': a folder name
//   "body": {                             // a `palpa rest` body made from a scan,
//     "surface": "scan.obj", "unit": "m", //   without "depth", "material" or "stiffness":
//     "clip": {...}, "edge": "12 mm",     //   those come from the fits
//     "density": "1000 kg/m^3", "rotation": {...}, "position": [...]
//   },                                    //   ("generate" instead of "surface" works too)
//   "locations": [
//     {"name": "thigh-left",
//      "position": ["120 mm", "80 mm", "40 mm"],   // on the scan, in its frame (before rotation)
//      "pokes": [                                  // one per punch radius
//        {"radius": "4 mm", "force": "raw/f.csv", "laser": "raw/l.csv", "calibration": "raw/c.csv",
//         "options": {"laser_columns": "t:ms,dist:mm"}},   // `palpa acquire poke` options
//        {"radius": "8 mm", "curve": "curves/r8.csv"}      // or a curve acquired already
//      ],
//      "ultrasound": {"force": "raw/us-force.csv", "interfaces": {"fat": "raw/fat.csv", "bone": "raw/bone.csv"},
//                     "depth_interface": "bone", "options": {"offset": "0.15 s"}},
//      // or, without ultrasound, the layer depths to search:
//      // "depth_search": {"from": "5 mm", "to": "30 mm", "count": 6}
//     }
//   ],
//   "fit": {"model": "neo-hookean", "poisson": 0.45, "lateral_size": "100 mm",
//           "contact": "frictionless", "mesh_level": 1, "steps": 10, "max_iterations": 50,
//           "depth_from": "whole", "fix": ["nu"]},   // `palpa fit` options; "poisson" the
//                                                     // datasets' (and the value "nu" is held at)
//   "shape_from": "thigh-left",           // optional, see below
//   "design": "chair.json",               // a `palpa design` scene: the support and the load;
//                                         // its "body" is replaced by the subject's
//   "pressure": {"locations": "raw/sensors.csv", "samples": "raw/samples.csv", "load": "300 N",
//                "options": {"trim": 0.1}}  // optional: measured on the design's initial support
// }
//
// The body carries the fits as one material's shape scaled to each location's
// small-strain Young's modulus, interpolated over the skin like the depths
// (tet/material_field.hpp): a handful of locations can tell a modulus field
// apart, far less a field of nonlinear shapes; a common shape keeps the
// body's energy one material's per quadrature point; and the modulus is what
// a fit determines best. The shape is the fit of "shape_from", by default the
// location whose fit has the lowest training error relative to its largest
// force.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/json.hpp"

namespace palpa::pipeline {

// One poke of a location: its punch radius and raw logs (or ready curve).
struct Poke {
  double radius = 0.0;                         // [m]
  std::string tag;                             // "r4mm": its curve's file name
  std::vector<std::filesystem::path> inputs;   // the logs, or the curve
  std::vector<std::string> acquire_args;       // `palpa acquire poke` options, without -o (empty: a ready curve)
};

struct Ultrasound {
  std::vector<std::filesystem::path> inputs;
  std::vector<std::string> acquire_args;       // `palpa acquire ultrasound` options, without -o
  std::string depth_interface;                 // whose rest depth is the layer's
};

struct DepthSearch {
  double from = 0.0, to = 0.0;  // [m]
  int count = 0;
};

struct Location {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // on the scan, its frame [m]
  std::vector<Poke> pokes;
  std::optional<Ultrasound> ultrasound;   // exactly one of ultrasound and depth_search
  std::optional<DepthSearch> depth_search;
};

struct PressureLogs {
  std::vector<std::filesystem::path> inputs;
  std::vector<std::string> acquire_args;  // `palpa acquire pressure` options without --mesh and -o
};

struct Subject {
  std::filesystem::path file;
  Json doc;                                 // the file as read
  std::string name;
  std::vector<Location> locations;
  Json dataset;                             // the fit datasets' common members (poisson, lateral_size, contact)
  std::vector<std::string> fit_args;        // `palpa fit` options
  std::string shape_from;                   // empty: the best-fitted location
  std::filesystem::path design;             // the design scene
  std::optional<PressureLogs> pressure;
};

// Reads and checks a subject file: the format, every key, the names (unique,
// usable as folder names), the punch radii (one poke per radius), every file
// it names exists. Throws palpa::Error (Input) naming the file, the field and
// the subject and location.
Subject read_subject(const std::filesystem::path& file);

// Checks that every location lies on the body: within max_distance of the
// skin surface that "body" describes (read and prepared here). Throws
// palpa::Error (Input) naming the subject, location and its distance.
void check_locations_on_body(const Subject& s, double max_distance = 5e-3);

// What a workflow runs for the subject (JSON): per location its pokes (tag,
// radius, inputs, `palpa acquire poke` arguments), its ultrasound (inputs,
// arguments) or depth search; the fit's arguments; the design scene; the
// pressure logs. Paths absolute.
Json subject_plan(const Subject& s);

// The fit dataset of one location: its curves (curve_dir/<tag>.csv), its
// layer depth (the rest depth of the ultrasound's depth interface in
// ultrasound_summary, from `palpa acquire ultrasound --summary`) or depth
// search, and the subject's dataset members. Curve paths are written relative
// to dataset_dir, where the dataset goes.
Json location_dataset(const Subject& s, const std::string& location, const std::filesystem::path& curve_dir,
                      const std::optional<std::filesystem::path>& ultrasound_summary,
                      const std::filesystem::path& dataset_dir);

// The subjects of a cohort file, {"palpa_cohort": 1, "subjects": ["s01/subject.json", ...]}
// (paths relative to it), or of a subject file alone. Throws palpa::Error
// (Input) for a subject that does not read (its message) and for two subjects
// of one name (naming both files).
std::vector<Subject> read_subjects(const std::filesystem::path& cohort_or_subject);

// The plans of several subjects: {"palpa_plan": 1, "subjects": [subject_plan, ...]}.
Json cohort_plan(const std::vector<Subject>& subjects);

// The location named `name`; throws palpa::Error (Input) listing the names.
const Location& find_location(const Subject& s, const std::string& name);

}  // namespace palpa::pipeline
