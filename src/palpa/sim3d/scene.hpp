// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Scenes of `palpa sim3d` (JSON): a tet body, its materials and supports,
// rigid obstacles with poses or indentation paths, gravity, contact and solver
// settings. Every quantity carries its unit ("5 mm", "12 kPa"); positions are
// metres inside.
//
// {
//   "palpa_scene": 1,
//   "body": {
//     "box": {"size": ["60 mm", "60 mm", "20 mm"], "cells": [12, 12, 4]},
//                                   // top face at z = 0, centred in x and y
//     // or "cylinder": {"radius": "22.57 mm", "height": "10 mm", "rim": "4 mm",
//     //               "level": 1, "segments": 96, "sector": "90 deg"}
//     // or "mesh": "body.vtu" (.vtu/.msh/.node/.ele), "unit": "mm"
//     "materials": [{"material": "foam.json", "density": "1000 kg/m^3",
//                    "regions": [0, 2]}],        // regions: omit for all tets
//     "element": "linear",    // or "nodal-pressure": volume change averaged
//                             // over each vertex's tets, for ν near 0.5
//     "stabilization": 0.1,   // nodal-pressure: share β of each tet's own
//                             // volume change kept (default 0)
//     "fixed": [{"set": "bottom", "components": "xyz"},
//               {"below": "-19 mm", "axis": "z"}]
//   },
//   "gravity": ["0 m/s^2", "0 m/s^2", "-9.81 m/s^2"],             // optional
//   "obstacles": [{
//     "name": "punch",
//     "shape": {"cylinder": {"radius": "5 mm", "height": "10 mm", "segments": 64}},
//              // or {"box": {"size": [...], "divisions": 4}}, {"sphere": {"radius": ...}},
//              // or {"file": "indenter.obj", "unit": "mm"}
//     "position": ["0 mm", "0 mm", "0 mm"],      // where the shape's origin starts
//     "rotation": {"axis": [1, 0, 0], "angle": "0 deg"},          // optional
//     "path": {"direction": [0, 0, -1], "depth": "3 mm"}          // optional
//   }],
//   "steps": 10,                                // equilibria along the paths
//   "contact": {"max_penetration": "0.05 mm"}   // or {"stiffness": "2000 N/m"}
//              // + "sampling": "vertices"|"surface", "subdivisions": 2,
//              //   "friction": "frictionless"|"stick"
//   "solver": {"line_search": "backtracking", "max_iterations": 100,
//              "force_tolerance": "1 uN"},
//   "dynamics": {"time_step": "5 ms", "mass_damping": "20 Hz",
//                "stiffness_damping": "1 ms", "max_steps": 400, "settle": "1 um"},
//   "local": {"margin": "10 mm"},               // simulate only near the obstacles
//   "output": {"frames_every": 1}
// }
//
// A cylinder stands on the z axis with its top face at z = 0; its (r, z) cells
// are those of `palpa poke`'s layer under a punch of radius "rim" at mesh
// "level" (0–4, default 1; graded toward a ring of nodes at the rim), swept
// around in "segments" equal angles (default 96; a cylinder obstacle with as
// many segments has its edge on the rim ring), over the whole circle or a
// "sector" from the +x axis toward +y (a quarter: "90 deg").
//
// Vertex sets for "fixed": a box's faces ("bottom" = "zmin", "top" = "zmax",
// "xmin", …); a cylinder's "bottom", "top", "side" and, for a sector,
// "sector_start" (the plane y = 0) and "sector_end"; "boundary" (every boundary
// vertex); "marker:N" (vertices of the boundary triangles with Gmsh physical
// tag N); or a half-space {"below"|
// "above": "<length>", "axis": "x"|"y"|"z"} (coordinate ≤ / ≥ the value).
// "components" is any of "x", "y", "z" (default "xyz").
//
// Shape origins: a cylinder's and a box's bottom face centre, a sphere's lowest
// point (shapes.hpp); a file's own origin. Each obstacle moves along its path
// by depth·s/steps at step s (all paths in lockstep).

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "palpa/body/contact_term.hpp"
#include "palpa/geometry/mesh.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::sim3d {

struct ObstacleSpec {
  std::string name;
  SurfaceMesh mesh;  // in its own frame [m]
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  bool has_path = false;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit
  double depth = 0.0;                                   // [m]
};

struct FixedSpec {
  std::string description;  // "bottom (xyz)"
  std::vector<int> vertices;
  std::array<bool, 3> components{true, true, true};
};

struct ContactSpec {
  double stiffness = 0.0;          // k [N/m] ([Pa/m] with Surface); 0: automatic from max_penetration
  double max_penetration = 0.0;    // target [m]; 0: 2% of the mean surface edge, ≤ 1% of the deepest path
  // Where the springs sit (body/contact_term.hpp): the boundary's vertices,
  // or subdivisions² points on each boundary triangle.
  body::ContactSampling sampling = body::ContactSampling::Vertices;
  int subdivisions = 2;
  // Frictionless, or Stick: a point that meets an obstacle stays where it met
  // it (a bonded punch face) while it is pressed.
  contact::Friction friction = contact::Friction::Frictionless;
};

struct SolverSpec {
  LineSearchKind line_search = LineSearchKind::Backtracking;
  int max_iterations = 100;
  double force_tolerance = 0.0;  // [N]; 0: automatic (see run.hpp)
};

struct DynamicsSpec {
  bool enabled = false;
  double time_step = 5e-3;          // [s]
  double mass_damping = 0.0;        // a [1/s]
  double stiffness_damping = 0.0;   // b [s]
  int max_steps = 400;
  double settle = 0.0;              // largest vertex move per step to call it settled [m]; 0: auto
};

struct LocalSpec {
  bool enabled = false;
  double margin = 0.01;  // [m] beyond the contact
};

struct Scene {
  std::filesystem::path file;
  std::string mesh_name;  // for messages
  TetMesh mesh;           // checked and oriented
  bool is_box = false;
  std::vector<tet::BodyMaterial> materials;
  Eigen::VectorXi element_material;
  tet::ElementChoice element;
  std::vector<FixedSpec> fixed;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::vector<ObstacleSpec> obstacles;
  int steps = 1;
  ContactSpec contact;
  SolverSpec solver;
  DynamicsSpec dynamics;
  LocalSpec local;
  int frames_every = 1;
};

// Reads and checks a scene; relative paths resolve against its folder. Throws
// palpa::Error (Input) naming the file and field for anything malformed: an
// unknown member, a missing or ill-formed quantity, a mesh that fails
// tet::prepare_tet_mesh, a region no material covers or covered twice, an
// unknown vertex set, a fixed set that is empty, an obstacle that is not a
// closed surface (checked when the simulation builds it), paths but steps < 1.
Scene read_scene(const std::filesystem::path& path);

}  // namespace palpa::sim3d
