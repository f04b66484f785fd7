// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/body_problem.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "palpa/core/error.hpp"
#include "palpa/core/stopwatch.hpp"
#include "palpa/rest/adjoint.hpp"

namespace palpa::design {

namespace {

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
T get(const std::string& in, std::size_t& at) {
  if (at + sizeof(T) > in.size()) throw Error(ErrorKind::Internal, "a body's shared evaluation is cut short");
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

}  // namespace

std::string pack_shared(const BodyEvaluation& e, bool gradient) {
  std::string out;
  put(out, static_cast<std::uint8_t>(e.ok));
  put(out, static_cast<std::int32_t>(e.error ? static_cast<int>(*e.error) : -1));
  put(out, static_cast<std::uint64_t>(e.failure.size()));
  out += e.failure;
  for (double v : {e.zeta, e.score.zeta_body, e.score.zeta_support, e.rest.max_penetration, e.state.stiffness,
                   e.seconds, e.adjoint_seconds}) {
    put(out, v);
  }
  put(out, static_cast<std::int32_t>(e.rest.newton_iterations));
  const bool with = gradient && e.ok && e.gradient.size() > 0;
  put(out, static_cast<std::int64_t>(with ? e.gradient.rows() : 0));
  if (with) out.append(reinterpret_cast<const char*>(e.gradient.data()), sizeof(double) * e.gradient.size());
  return out;
}

BodyEvaluation unpack_shared(const std::string& in) {
  BodyEvaluation e;
  std::size_t at = 0;
  e.ok = get<std::uint8_t>(in, at) != 0;
  if (const auto kind = get<std::int32_t>(in, at); kind >= 0) e.error = static_cast<ErrorKind>(kind);
  const auto n = get<std::uint64_t>(in, at);
  if (at + n > in.size()) throw Error(ErrorKind::Internal, "a body's shared evaluation is cut short");
  e.failure = in.substr(at, n);
  at += n;
  e.zeta = e.score.zeta = get<double>(in, at);
  e.score.zeta_body = get<double>(in, at);
  e.score.zeta_support = get<double>(in, at);
  e.rest.max_penetration = get<double>(in, at);
  e.state.stiffness = get<double>(in, at);
  e.seconds = get<double>(in, at);
  e.adjoint_seconds = get<double>(in, at);
  e.rest.newton_iterations = get<std::int32_t>(in, at);
  if (const auto rows = get<std::int64_t>(in, at); rows > 0) {
    e.gradient.resize(rows, 3);
    if (at + sizeof(double) * e.gradient.size() != in.size()) {
      throw Error(ErrorKind::Internal, "a body's shared gradient is cut short");
    }
    std::memcpy(e.gradient.data(), in.data() + at, sizeof(double) * e.gradient.size());
  }
  return e;
}

namespace {

void put_vector(std::string& out, const double* data, std::size_t n) {
  put(out, static_cast<std::uint64_t>(n));
  out.append(reinterpret_cast<const char*>(data), sizeof(double) * n);
}

std::vector<double> get_vector(const std::string& in, std::size_t& at) {
  const auto n = get<std::uint64_t>(in, at);
  if (at + sizeof(double) * n > in.size()) throw Error(ErrorKind::Internal, "a body's shared state is cut short");
  std::vector<double> v(n);
  std::memcpy(v.data(), in.data() + at, sizeof(double) * n);
  at += sizeof(double) * n;
  return v;
}

Eigen::VectorXd as_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace

std::string pack_state(const rest::RestState& s) {
  std::string out;
  put_vector(out, s.x.data(), static_cast<std::size_t>(s.x.size()));
  put_vector(out, s.core.rotation.data(), 9);
  put_vector(out, s.core.omega.data(), 3);
  put_vector(out, s.spring_areas.data(), s.spring_areas.size());
  put(out, s.stiffness);
  put_vector(out, s.support.data(), static_cast<std::size_t>(s.support.size()));
  return out;
}

rest::RestState unpack_state(const std::string& in) {
  rest::RestState s;
  std::size_t at = 0;
  s.x = as_vector(get_vector(in, at));
  const std::vector<double> R = get_vector(in, at), w = get_vector(in, at);
  if (R.size() != 9 || w.size() != 3) throw Error(ErrorKind::Internal, "a body's shared core pose is malformed");
  s.core.rotation = Eigen::Map<const Eigen::Matrix3d>(R.data());
  s.core.omega = Eigen::Map<const Eigen::Vector3d>(w.data());
  s.spring_areas = get_vector(in, at);
  s.stiffness = get<double>(in, at);
  s.support = as_vector(get_vector(in, at));
  return s;
}

BodyProblem::BodyProblem(DesignBody body, const SurfaceMesh& support, const ScoreOptions& score, int slots,
                         int trial_newton_iterations)
    : body_(std::move(body)) {
  const auto t0 = Clock::now();
  sims_.push_back(std::make_unique<rest::RestSimulation>(body_.body, support, body_.rest));
  rest::RestSimulation& first = *sims_.front();
  initial_rest_ = first.solve();
  equilibrium_seconds_ = seconds_since(t0);
  first.freeze_contact_model();
  // One line per design iteration from here on, not one per equilibrium.
  first.set_log_solves(false);
  initial_state_ = first.state();
  body_.rest.log_solves = false;
  rest::RestOptions frozen = body_.rest;
  frozen.stiffness = initial_rest_.stiffness;
  frozen.update_areas = false;
  for (int i = 1; i < slots; ++i) {
    sims_.push_back(std::make_unique<rest::RestSimulation>(body_.body, support, frozen));
    sims_.back()->freeze_contact_model();
  }
  // A trial whose warm-started equilibrium needs many Newton iterations has
  // moved too far: it fails (a shorter step is tried) rather than grinding on.
  for (auto& sim : sims_) {
    NewtonOptions no = sim->newton().options();
    no.max_iterations = std::min(no.max_iterations, trial_newton_iterations);
    sim->newton().set_options(no);
  }
  score_ = std::make_unique<ErgonomicScore>(first, score);
}

BodyProblem::~BodyProblem() = default;

BodyEvaluation BodyProblem::evaluate(const Eigen::MatrixX3d& X, const rest::RestState& warm, bool gradient, int slot) {
  const auto t0 = Clock::now();
  rest::RestSimulation& sim = simulation(slot);
  BodyEvaluation ev;
  sim.restore(warm);
  try {
    sim.set_support_vertices(X);
    ev.rest = sim.solve();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Solver) throw;
    ev.failure = e.what();
    ev.seconds = seconds_since(t0);
    return ev;
  }
  ev.state = sim.state();
  ev.score = score_->evaluate(sim, gradient);
  ev.zeta = ev.score.zeta;
  ev.ok = std::isfinite(ev.zeta);
  if (!ev.ok) ev.failure = "the score is not finite";
  if (gradient && ev.ok) {
    const auto ta = Clock::now();
    Eigen::MatrixX3d through;
    if (const AdjointStatus st = rest::shape_derivative(sim, ev.score.d_body, ev.score.d_support, through); !st.ok()) {
      ev.ok = false;
      ev.failure = st.message();
    } else {
      ev.gradient = through + ev.score.d_support_area;
    }
    ev.adjoint_seconds = seconds_since(ta);
  }
  ev.seconds = seconds_since(t0);
  return ev;
}

bool BodyProblem::out_of_band(double max_penetration) const {
  const auto [low, high] = sims_.front()->accepted_penetration();
  const double ratio = max_penetration / body_.rest.target_penetration;
  return max_penetration > 0.0 && (ratio < low || ratio > high);
}

rest::RestResult BodyProblem::refreeze(const Eigen::MatrixX3d& X, const rest::RestState& state) {
  rest::RestSimulation& sim = *sims_.front();
  sim.restore(state);
  sim.set_support_vertices(X);
  return sim.refreeze_contact_model();
}

}  // namespace palpa::design
