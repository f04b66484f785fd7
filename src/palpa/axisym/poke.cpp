// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/axisym/poke.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::axisym {

namespace {

constexpr double kPi = 3.14159265358979323846;
using material::EvalOrder;
using material::PsdProjection;

// Element loops run in parallel over blocks of this many elements.
constexpr std::size_t kGrain = 64;

}  // namespace

std::string_view to_string(PunchContact c) noexcept {
  return c == PunchContact::Stick ? "stick" : "frictionless";
}

PunchContact parse_punch_contact(std::string_view name) {
  if (name == "stick") return PunchContact::Stick;
  if (name == "frictionless") return PunchContact::Frictionless;
  throw_input_error(fmt::format("unknown contact '{}'", name), ErrorContext{},
                    "stick or frictionless");
}

std::string_view to_string(PokeTest t) noexcept {
  return t == PokeTest::Indentation ? "indentation" : "compression";
}

PokeTest parse_poke_test(std::string_view name) {
  if (name == "indentation") return PokeTest::Indentation;
  if (name == "compression") return PokeTest::Compression;
  throw_input_error(fmt::format("unknown test '{}'", name), ErrorContext{},
                    "indentation or compression");
}

PunchContact parse_platen_contact(std::string_view name) {
  if (name == "bonded") return PunchContact::Stick;
  if (name == "frictionless") return PunchContact::Frictionless;
  throw_input_error(fmt::format("unknown platen contact '{}'", name), ErrorContext{},
                    "bonded or frictionless");
}

std::string_view platen_contact_name(PunchContact c) noexcept {
  return c == PunchContact::Stick ? "bonded" : "frictionless";
}

// ---------------------------------------------------------------- PokeModel

PokeModel::PokeModel(const material::Material& material, const PokeSetup& setup)
    : material_(material.clone()),
      setup_(setup),
      mesh_(setup.test == PokeTest::Compression ? make_cylinder_mesh(setup.geometry, setup.mesh_level)
                                                : make_layer_mesh(setup.geometry, setup.mesh_level)) {
  const bool compression = setup.test == PokeTest::Compression;
  if (compression) setup_.geometry = mesh_.geometry;  // the sample radius resolved
  const double a = mesh_.geometry.punch_radius;
  const double rho = setup.fillet_radius;
  if (compression && rho != 0.0) {
    throw_input_error(fmt::format("fillet radius {} m given for a compression test", rho), ErrorContext{},
                      "no fillet: it rounds the rim of an indentation punch, and the platens have none");
  }
  if (!std::isfinite(rho) || rho < 0.0 || !(rho < a)) {
    throw_input_error(fmt::format("fillet radius {} m is outside [0, punch radius {} m)", rho, a),
                      ErrorContext{}, "0 <= fillet < punch radius");
  }
  if (!(setup.penalty_factor > 0.0) || !std::isfinite(setup.penalty_factor)) {
    throw_input_error(fmt::format("contact penalty factor {} is not positive", setup.penalty_factor),
                      ErrorContext{}, "a positive factor (default 1000)");
  }
  punch_ = PunchShape{a, rho, 0.0};

  const Eigen::Index n_nodes = mesh_.num_nodes();
  geometry_.reserve(static_cast<std::size_t>(mesh_.num_elements()));
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    Eigen::Matrix<double, 2, 4> rest;
    for (int k = 0; k < 4; ++k) rest.col(k) = mesh_.nodes.row(mesh_.quads(e, k)).transpose();
    geometry_.push_back(quad_geometry(rest));
  }

  // Constraints.
  std::vector<bool> fixed(static_cast<std::size_t>(2 * n_nodes), false);
  for (int n : mesh_.axis_nodes) fixed[static_cast<std::size_t>(2 * n)] = true;
  for (int n : mesh_.base_nodes) {
    // Indentation: the layer is bonded to its base; compression: the base
    // platen holds u_z and, bonded, also u_r.
    if (!compression || setup.contact == PunchContact::Stick) fixed[static_cast<std::size_t>(2 * n)] = true;
    fixed[static_cast<std::size_t>(2 * n + 1)] = true;
    if (compression) platen_base_nodes_.push_back(n);
  }
  const double face_edge = a - rho + 1e-9 * a;
  std::vector<int> outside_face;
  for (int n : mesh_.top_nodes) {
    if (mesh_.nodes(n, 0) <= face_edge) {
      face_nodes_.push_back(n);
      fixed[static_cast<std::size_t>(2 * n + 1)] = true;
      if (setup.contact == PunchContact::Stick) fixed[static_cast<std::size_t>(2 * n)] = true;
    } else {
      outside_face.push_back(n);
    }
  }
  full_to_free_.assign(static_cast<std::size_t>(2 * n_nodes), -1);
  for (Eigen::Index d = 0; d < 2 * n_nodes; ++d) {
    if (!fixed[static_cast<std::size_t>(d)]) {
      full_to_free_[static_cast<std::size_t>(d)] = static_cast<int>(free_dofs_.size());
      free_dofs_.push_back(static_cast<int>(d));
    }
  }

  // Ring areas of the top nodes: the annulus between the midpoints to their
  // neighbours.
  ring_area_.assign(static_cast<std::size_t>(n_nodes), 0.0);
  const auto& top = mesh_.top_nodes;
  for (std::size_t k = 0; k < top.size(); ++k) {
    const double r = mesh_.nodes(top[k], 0);
    const double lo = k == 0 ? r : 0.5 * (r + mesh_.nodes(top[k - 1], 0));
    const double hi = k + 1 == top.size() ? r : 0.5 * (r + mesh_.nodes(top[k + 1], 0));
    ring_area_[static_cast<std::size_t>(top[k])] = kPi * (hi * hi - lo * lo);
    // The base has the same columns.
    if (compression) ring_area_[static_cast<std::size_t>(mesh_.base_nodes[k])] = kPi * (hi * hi - lo * lo);
  }
  const double mu0 = material::small_strain_constants(*material_).mu;
  penalty_per_area_ = setup.penalty_factor * mu0 / mesh_.rim_cell_size;
  // Contact checks. Indentation: the top nodes beside the punch face against
  // the punch. Compression: the side-wall nodes against both platens, with
  // their share 2π R ℓ of the wall (ℓ: half the rest heights of the rows on
  // either side).
  for (int n : outside_face) {
    contacts_.push_back({n, Obstacle::Punch, penalty_per_area_ * ring_area_[static_cast<std::size_t>(n)]});
  }
  if (compression) {
    for (int n : side_wall_nodes(mesh_)) {
      const double ell = 0.5 * (mesh_.nodes(n + mesh_.columns, 1) - mesh_.nodes(n - mesh_.columns, 1));
      const double k = penalty_per_area_ * 2.0 * kPi * a * ell;
      contacts_.push_back({n, Obstacle::TopPlaten, k});
      contacts_.push_back({n, Obstacle::BasePlaten, k});
    }
  }
  if (!(setup.fbar_stabilization >= 0.0) || !std::isfinite(setup.fbar_stabilization)) {
    throw_input_error(fmt::format("F-bar stabilization {} is negative", setup.fbar_stabilization),
                      ErrorContext{}, "a factor >= 0 (default 1)");
  }
  element_.formulation = setup.element;
  element_.stabilization = setup.fbar_stabilization * mu0;
  {
    constexpr double kSafety = 64.0;
    const double eps = std::numeric_limits<double>::epsilon();
    double volume = 0.0;
    double worst = 0.0;
    for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
      double v = 0.0;
      for (double w : geometry_[static_cast<std::size_t>(e)].weight) v += w;
      const Eigen::Vector2d diag = mesh_.nodes.row(mesh_.quads(e, 2)) - mesh_.nodes.row(mesh_.quads(e, 0));
      const double h = std::min(std::abs(diag[0]), std::abs(diag[1]));
      volume += v;
      worst = std::max(worst, v / h);
    }
    energy_noise_floor_ = kSafety * eps * mu0 * volume;
    gradient_noise_floor_ = kSafety * eps * mu0 * worst;
  }

  // Hessian pattern over the free DOFs (lower triangle) and element slots.
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(mesh_.num_elements()) * 36);
  const auto local_free = [&](Eigen::Index e, int i) {
    const int node = mesh_.quads(e, i / 2);
    return full_to_free_[static_cast<std::size_t>(2 * node + i % 2)];
  };
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 8; ++j) {
        const int fi = local_free(e, i);
        const int fj = local_free(e, j);
        if (fi >= 0 && fj >= 0 && fi >= fj) trip.emplace_back(fi, fj, 0.0);
      }
    }
  }
  const auto n_free = static_cast<Eigen::Index>(free_dofs_.size());
  pattern_.resize(n_free, n_free);
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  const auto slot = [&](int row, int col) { return lower_slot(pattern_, row, col); };
  element_slots_.resize(static_cast<std::size_t>(mesh_.num_elements()));
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    auto& s = element_slots_[static_cast<std::size_t>(e)];
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 8; ++j) {
        const int fi = local_free(e, i);
        const int fj = local_free(e, j);
        s[static_cast<std::size_t>(8 * j + i)] = (fi >= 0 && fj >= 0 && fi >= fj) ? slot(fi, fj) : -1;
      }
    }
  }
  for (const ContactCheck& c : contacts_) {
    const int fr = full_to_free_[static_cast<std::size_t>(2 * c.node)];
    const int fz = full_to_free_[static_cast<std::size_t>(2 * c.node + 1)];
    contact_slots_.push_back({slot(fr, fr), slot(fz, fr), slot(fz, fz)});
  }
}

PokeModel::~PokeModel() = default;

void PokeModel::set_material_params(const Eigen::VectorXd& theta) { material_->set_params(theta); }

void PokeModel::set_depth(double depth) { punch_.depth = depth; }

Eigen::VectorXd PokeModel::full_displacement(const Eigen::VectorXd& x) const {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * mesh_.num_nodes());
  for (std::size_t k = 0; k < free_dofs_.size(); ++k) u[free_dofs_[k]] = x[static_cast<Eigen::Index>(k)];
  for (int n : face_nodes_) u[2 * n + 1] = -punch_.depth;
  return u;
}

Eigen::MatrixX2d PokeModel::displacements(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(u.data(), mesh_.num_nodes(), 2);
}

Vec8 PokeModel::element_dofs(const Eigen::VectorXd& u, Eigen::Index e) const {
  Vec8 ue;
  for (int k = 0; k < 4; ++k) ue.segment<2>(2 * k) = u.segment<2>(2 * mesh_.quads(e, k));
  return ue;
}

PunchDistance PokeModel::distance(const ContactCheck& c, const Eigen::VectorXd& u) const {
  const Eigen::Vector2d p = mesh_.nodes.row(c.node).transpose() + u.segment<2>(2 * c.node);
  switch (c.obstacle) {
    case Obstacle::Punch: return punch_distance(punch_, p);
    case Obstacle::TopPlaten: return platen_distance(-punch_.depth, PlatenSide::Above, p);
    case Obstacle::BasePlaten: return platen_distance(-mesh_.geometry.thickness, PlatenSide::Below, p);
  }
  return {};
}

double PokeModel::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const {
  const Eigen::VectorXd u = full_displacement(x);
  const auto n_el = static_cast<std::size_t>(mesh_.num_elements());
  const EvalOrder order = g != nullptr ? EvalOrder::Gradient : EvalOrder::Energy;
  std::vector<double> energies(n_el, 0.0);
  Eigen::Matrix<double, 8, Eigen::Dynamic> grads;
  if (g != nullptr) grads.resize(8, static_cast<Eigen::Index>(n_el));
  std::atomic<bool> admissible{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_el, kGrain), [&](const auto& range) {
    ElementResult r;
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      const auto ei = static_cast<Eigen::Index>(e);
      if (!element_evaluate(*material_, geometry_[e], element_dofs(u, ei), order, PsdProjection::None, r, element_)) {
        admissible = false;
        return;
      }
      energies[e] = r.energy;
      if (g != nullptr) grads.col(ei) = r.gradient;
    }
  });
  if (!admissible) return std::numeric_limits<double>::infinity();
  double total = 0.0;
  for (double v : energies) total += v;
  if (g != nullptr) {
    g->setZero(num_dofs());
    for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
      for (int i = 0; i < 8; ++i) {
        const int f = full_to_free_[static_cast<std::size_t>(2 * mesh_.quads(e, i / 2) + i % 2)];
        if (f >= 0) (*g)[f] += grads(i, e);
      }
    }
  }
  // Contact: ½ k φ² for every surface node inside the punch (or a platen).
  for (const ContactCheck& check : contacts_) {
    const PunchDistance d = distance(check, u);
    if (d.phi >= 0.0) continue;
    const double k = check.stiffness;
    total += 0.5 * k * d.phi * d.phi;
    if (g != nullptr) {
      const Eigen::Vector2d f = k * d.phi * d.normal;
      for (int c = 0; c < 2; ++c) {
        const int fi = full_to_free_[static_cast<std::size_t>(2 * check.node + c)];
        if (fi >= 0) (*g)[fi] += f[c];
      }
    }
  }
  return total;
}

double PokeModel::energy(const Eigen::VectorXd& x) const { return evaluate(x, nullptr); }

void PokeModel::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const { evaluate(x, &g); }

double PokeModel::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  return evaluate(x, &g);
}

void PokeModel::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  assemble_hessian(x, true_hessian_, H);
}

bool PokeModel::projected_hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  assemble_hessian(x, false, H);
  return true;
}

void PokeModel::assemble_hessian(const Eigen::VectorXd& x, bool true_hessian, Eigen::SparseMatrix<double>& H) const {
  if (H.rows() != pattern_.rows() || H.nonZeros() != pattern_.nonZeros() || !H.isCompressed()) {
    H = pattern_;
  }
  std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
  const Eigen::VectorXd u = full_displacement(x);
  const auto n_el = static_cast<std::size_t>(mesh_.num_elements());
  const PsdProjection proj = true_hessian ? PsdProjection::None : PsdProjection::Clamp;
  std::vector<Mat8> blocks(n_el);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_el, kGrain), [&](const auto& range) {
    ElementResult r;
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      if (!element_evaluate(*material_, geometry_[e], element_dofs(u, static_cast<Eigen::Index>(e)),
                            EvalOrder::Hessian, proj, r, element_)) {
        throw Error(ErrorKind::Internal, "Hessian requested at an inverted configuration");
      }
      blocks[e] = r.hessian;
    }
  });
  double* values = H.valuePtr();
  for (std::size_t e = 0; e < n_el; ++e) {
    const auto& slots = element_slots_[e];
    const double* h = blocks[e].data();
    for (std::size_t k = 0; k < 64; ++k) {
      if (slots[k] >= 0) values[slots[k]] += h[k];
    }
  }
  for (std::size_t c = 0; c < contacts_.size(); ++c) {
    const PunchDistance d = distance(contacts_[c], u);
    if (d.phi >= 0.0) continue;
    const double k = contacts_[c].stiffness;
    // k (n nᵀ + φ ∇²φ); the curvature term is negative semi-definite inside a
    // convex punch, so the projected Hessian keeps only k n nᵀ.
    Eigen::Matrix2d hc = k * d.normal * d.normal.transpose();
    if (true_hessian) hc += k * d.phi * d.hessian;
    values[contact_slots_[c][0]] += hc(0, 0);
    values[contact_slots_[c][1]] += hc(1, 0);
    values[contact_slots_[c][2]] += hc(1, 1);
  }
}

Eigen::Index PokeModel::num_params() const { return material_->num_params(); }

void PokeModel::gradient_param_jacobian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& J) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::Index p = material_->num_params();
  const auto n_el = static_cast<std::size_t>(mesh_.num_elements());
  std::vector<Eigen::MatrixXd> blocks(n_el);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_el, kGrain), [&](const auto& range) {
    Eigen::MatrixXd work3(3, p);
    Eigen::MatrixXd work5(5, p);
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      blocks[e].resize(8, p);
      element_dgradient_dparam(*material_, geometry_[e], element_dofs(u, static_cast<Eigen::Index>(e)),
                               work3, work5, blocks[e], element_);
    }
  });
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(num_dofs(), p);
  for (std::size_t e = 0; e < n_el; ++e) {
    for (int i = 0; i < 8; ++i) {
      const int f = full_to_free_[static_cast<std::size_t>(2 * mesh_.quads(static_cast<Eigen::Index>(e), i / 2) + i % 2)];
      if (f >= 0) dense.row(f) += blocks[e].row(i);
    }
  }
  J = dense.sparseView();
}

Eigen::VectorXd PokeModel::gradient_param_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& lambda) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::Index p = material_->num_params();
  const auto n_el = static_cast<std::size_t>(mesh_.num_elements());
  // Deterministic: the same state gives the same bits however the threads
  // are scheduled, so fits (and fits resumed from a checkpoint) repeat
  // exactly on a busy machine too.
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n_el, kGrain), Eigen::VectorXd(Eigen::VectorXd::Zero(p)),
      [&](const auto& range, Eigen::VectorXd acc) {
        Eigen::MatrixXd work3(3, p);
        Eigen::MatrixXd work5(5, p);
        Eigen::MatrixXd block(8, p);
        for (std::size_t e = range.begin(); e != range.end(); ++e) {
          const auto ei = static_cast<Eigen::Index>(e);
          Vec8 le = Vec8::Zero();
          bool any = false;
          for (int i = 0; i < 8; ++i) {
            const int f = full_to_free_[static_cast<std::size_t>(2 * mesh_.quads(ei, i / 2) + i % 2)];
            if (f >= 0) {
              le[i] = lambda[f];
              any = true;
            }
          }
          if (!any) continue;
          element_dgradient_dparam(*material_, geometry_[e], element_dofs(u, ei), work3, work5, block, element_);
          acc.noalias() += block.transpose() * le;
        }
        return acc;
      },
      [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) -> Eigen::VectorXd { return a + b; });
}

Eigen::VectorXd PokeModel::full_elastic_gradient(const Eigen::VectorXd& u) const {
  const auto n_el = static_cast<std::size_t>(mesh_.num_elements());
  Eigen::Matrix<double, 8, Eigen::Dynamic> grads(8, static_cast<Eigen::Index>(n_el));
  std::atomic<bool> admissible{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_el, kGrain), [&](const auto& range) {
    ElementResult r;
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      const auto ei = static_cast<Eigen::Index>(e);
      if (!element_evaluate(*material_, geometry_[e], element_dofs(u, ei), EvalOrder::Gradient,
                            PsdProjection::None, r, element_)) {
        admissible = false;
        return;
      }
      grads.col(ei) = r.gradient;
    }
  });
  if (!admissible) throw Error(ErrorKind::Internal, "force requested at an inverted configuration");
  Eigen::VectorXd g = Eigen::VectorXd::Zero(u.size());
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    for (int i = 0; i < 8; ++i) g[2 * mesh_.quads(e, i / 2) + i % 2] += grads(i, e);
  }
  return g;
}

double PokeModel::punch_force(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::VectorXd g = full_elastic_gradient(u);
  double force = 0.0;
  for (int n : face_nodes_) force -= g[2 * n + 1];
  for (const ContactCheck& c : contacts_) {
    if (!pushes_down(c.obstacle)) continue;
    const PunchDistance d = distance(c, u);
    if (d.phi >= 0.0) continue;
    force += c.stiffness * d.phi * d.normal[1];
  }
  return force;
}

void PokeModel::punch_force_derivatives(const Eigen::VectorXd& x, Eigen::VectorXd& dfdx,
                                        Eigen::VectorXd& dfdtheta) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::Index p = material_->num_params();
  dfdx.setZero(num_dofs());
  dfdtheta.setZero(p);
  std::vector<bool> is_face(static_cast<std::size_t>(mesh_.num_nodes()), false);
  for (int n : face_nodes_) is_face[static_cast<std::size_t>(n)] = true;
  ElementResult r;
  Eigen::MatrixXd work3(3, p);
  Eigen::MatrixXd work5(5, p);
  Eigen::MatrixXd dg(8, p);
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    bool touches = false;
    for (int k = 0; k < 4; ++k) touches = touches || is_face[static_cast<std::size_t>(mesh_.quads(e, k))];
    if (!touches) continue;
    const Vec8 ue = element_dofs(u, e);
    const auto& geo = geometry_[static_cast<std::size_t>(e)];
    element_evaluate(*material_, geo, ue, EvalOrder::Hessian, PsdProjection::None, r, element_);
    element_dgradient_dparam(*material_, geo, ue, work3, work5, dg, element_);
    for (int k = 0; k < 4; ++k) {
      if (!is_face[static_cast<std::size_t>(mesh_.quads(e, k))]) continue;
      const int row = 2 * k + 1;  // local u_z of the face node
      dfdtheta -= dg.row(row).transpose();
      for (int j = 0; j < 8; ++j) {
        const int f = full_to_free_[static_cast<std::size_t>(2 * mesh_.quads(e, j / 2) + j % 2)];
        if (f >= 0) dfdx[f] -= r.hessian(row, j);
      }
    }
  }
  for (const ContactCheck& check : contacts_) {
    if (!pushes_down(check.obstacle)) continue;
    const PunchDistance d = distance(check, u);
    if (d.phi >= 0.0) continue;
    const double k = check.stiffness;
    // ∂(k φ n_z)/∂p = k (n_z n + φ ∇²φ row z)
    const Eigen::Vector2d row = k * (d.normal[1] * d.normal + d.phi * d.hessian.row(1).transpose());
    for (int c = 0; c < 2; ++c) {
      const int f = full_to_free_[static_cast<std::size_t>(2 * check.node + c)];
      if (f >= 0) dfdx[f] += row[c];
    }
  }
}

PokeModel::Diagnostics PokeModel::diagnostics(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  Diagnostics d;
  d.min_jacobian = std::numeric_limits<double>::infinity();
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    d.min_jacobian = std::min(d.min_jacobian, element_min_jacobian(geometry_[static_cast<std::size_t>(e)], element_dofs(u, e)));
  }
  for (const ContactCheck& c : contacts_) {
    const double phi = distance(c, u).phi;
    if (phi < 0.0) {
      ++d.contact_nodes;
      d.max_penetration = std::max(d.max_penetration, -phi);
    }
  }
  return d;
}

std::vector<ElementState> PokeModel::element_states(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  std::vector<ElementState> out(static_cast<std::size_t>(mesh_.num_elements()));
  for (Eigen::Index e = 0; e < mesh_.num_elements(); ++e) {
    out[static_cast<std::size_t>(e)] =
        element_state(*material_, geometry_[static_cast<std::size_t>(e)], element_dofs(u, e), element_);
  }
  return out;
}

bool PokeModel::gradient_depth_derivative(const Eigen::VectorXd& x, double eps, Eigen::VectorXd& dg) {
  if (!(eps > 0.0) || !std::isfinite(eps)) {
    throw Error(ErrorKind::Internal, "depth difference must be positive");
  }
  const double depth = punch_.depth;
  Eigen::VectorXd g_minus;
  punch_.depth = depth + eps;
  const bool plus = std::isfinite(evaluate(x, &dg));
  punch_.depth = depth - eps;
  const bool minus = plus && std::isfinite(evaluate(x, &g_minus));
  punch_.depth = depth;
  if (!minus) return false;
  dg = (dg - g_minus) / (2.0 * eps);
  return dg.allFinite();
}

std::vector<char> PokeModel::contact_set(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  std::vector<char> active(contacts_.size(), 0);
  for (std::size_t c = 0; c < contacts_.size(); ++c) active[c] = distance(contacts_[c], u).phi < 0.0 ? 1 : 0;
  return active;
}

int PokeModel::separate_new_contacts(Eigen::VectorXd& x, const std::vector<char>& previous) const {
  if (previous.size() != contacts_.size()) {
    throw Error(ErrorKind::Internal, "contact set of another model");
  }
  const Eigen::VectorXd u = full_displacement(x);
  int moved = 0;
  for (std::size_t c = 0; c < contacts_.size(); ++c) {
    if (previous[c] != 0) continue;
    const PunchDistance d = distance(contacts_[c], u);
    if (d.phi >= 0.0) continue;
    const int node = contacts_[c].node;
    for (int k = 0; k < 2; ++k) {
      const int f = full_to_free_[static_cast<std::size_t>(2 * node + k)];
      if (f >= 0) x[f] -= (1.0 - 1.0 / setup_.penalty_factor) * d.phi * d.normal[k];
    }
    ++moved;
  }
  return moved;
}

Eigen::VectorXd PokeModel::contact_pressure(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::VectorXd g = full_elastic_gradient(u);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(mesh_.num_nodes());
  for (int n : face_nodes_) {
    const double area = ring_area_[static_cast<std::size_t>(n)];
    if (area > 0.0) p[n] = -g[2 * n + 1] / area;
  }
  for (int n : platen_base_nodes_) {
    const double area = ring_area_[static_cast<std::size_t>(n)];
    if (area > 0.0) p[n] = g[2 * n + 1] / area;
  }
  for (const ContactCheck& c : contacts_) {
    const double phi = distance(c, u).phi;
    if (phi < 0.0) p[c.node] = -penalty_per_area_ * phi;
  }
  return p;
}

}  // namespace palpa::axisym
