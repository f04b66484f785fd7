// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The body carries the fits (pipeline step "body"): from each location's
// fitted material and layer depth, the depth and modulus samples over the
// skin, the material's common shape (pipeline/subject.hpp says why), and the
// rest and design scenes of the subject's body made of them.
//
// The folder it writes:
//   depths.csv    x_m,y_m,z_m,depth_m: each location's layer depth (the
//                 ultrasound's, or the one its fit found)
//   moduli.csv    x_m,y_m,z_m,youngs_modulus_Pa: each fit's small-strain E
//   material.json the shape: the fitted material of one location, as fitted
//   fields.json   per location its figures, and which location gave the shape
//   rest.json     the design scene's support and load under "palpa_rest"
//   design.json   the design scene with the subject's body
// The scenes' body is the subject's with "depth", "stiffness" and "material"
// set to these files; every other relative path in them is made absolute.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "palpa/pipeline/subject.hpp"

namespace palpa::pipeline {

struct LocationFit {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // [m], the scan's frame
  double young = 0.0;           // small-strain E of the fitted material [Pa]
  double poisson = 0.0;
  double depth = 0.0;           // layer depth [m]
  bool depth_searched = false;  // found by the fit (else measured)
  double relative_error = 0.0;  // RMS over the training curves of (curve's RMS error / its largest force)
  std::string termination;      // the fit's
  std::filesystem::path folder; // the fit's output folder
};

struct BodyFields {
  std::vector<LocationFit> fits;  // in the subject's order
  std::size_t shape = 0;          // index of the location whose material is the shape
};

// Reads each location's fit from fits/<location>/ (material.json,
// report.json). Throws palpa::Error (Input) naming the subject, location and
// file of a fit that is missing or failed.
BodyFields read_location_fits(const Subject& s, const std::filesystem::path& fits);

// Writes the folder described above, all files or none.
void write_body_fields(const Subject& s, const BodyFields& f, const std::filesystem::path& out);

}  // namespace palpa::pipeline
