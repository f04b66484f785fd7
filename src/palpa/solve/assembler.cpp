// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/assembler.hpp"

#include <algorithm>
#include <atomic>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "palpa/core/error.hpp"
#include "palpa/solve/system.hpp"

namespace palpa {

namespace {

std::uint64_t pair_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Stencil Hessians are evaluated this many at a time into one buffer, of at
// most kBuffer doubles.
constexpr Eigen::Index kChunk = 2048;
constexpr Eigen::Index kBuffer = Eigen::Index{1} << 22;
constexpr std::size_t kGrain = 64;

}  // namespace

int Assembler::local_dofs(int v, int* out) const {
  if (map_->attached(v)) {
    const int nc = static_cast<int>(map_->num_core_dofs());
    for (int k = 0; k < nc; ++k) out[k] = static_cast<int>(map_->num_vertex_dofs()) + k;
    return nc;
  }
  for (int c = 0; c < 3; ++c) out[c] = map_->dof(3 * v + c);
  return 3;
}

Assembler::Assembler(const DofMap& map, std::vector<const Term*> terms) : map_(&map), terms_(std::move(terms)) {
  attached_index_.assign(static_cast<std::size_t>(map.num_vertices()), -1);
  if (map.has_core()) {
    const std::vector<int>& attached = map.core().attached;
    for (std::size_t i = 0; i < attached.size(); ++i) attached_index_[static_cast<std::size_t>(attached[i])] = static_cast<int>(i);
  }
  const Eigen::Index n = map.num_dofs();
  const auto nv = static_cast<int>(map.num_vertices());
  const int nc = static_cast<int>(map.num_core_dofs());
  // Every (a, b) block of the sum, in one fixed order, with the DOFs it lands
  // on; run twice: once for the pattern, once for the slots.
  std::vector<std::array<int, 2>> pairs;
  for (const Term* t : terms_) {
    for (const auto& [a, b] : t->vertex_pairs()) {
      if (a == b) continue;
      pairs.push_back({a, b});
      pairs.push_back({b, a});
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());

  const auto for_each_entry = [&](auto&& visit_stencil_entry, auto&& visit_block_entry) {
    // Element stencils.
    for (std::size_t ti = 0; ti < terms_.size(); ++ti) {
      const Term& t = *terms_[ti];
      const int K = t.stencil_size();
      if (K == 0) continue;
      std::vector<int> v;
      for (Eigen::Index s = 0; s < t.num_stencils(); ++s) {
        v.resize(static_cast<std::size_t>(K));
        v.resize(static_cast<std::size_t>(t.stencil(s, v.data())));
        const bool core = std::any_of(v.begin(), v.end(), [&](int w) { return map.attached(w); });
        visit_stencil_entry(ti, s, core, v);
      }
    }
    // Every vertex's own block, then the named pairs.
    for (int w = 0; w < nv; ++w) visit_block_entry(w, w);
    for (const auto& [a, b] : pairs) visit_block_entry(a, b);
  };

  // The DOF pairs of block (a, b), in slot order (columns outer).
  const auto block_entries = [&](int a, int b, auto&& f) {
    int la[6], lb[6];
    const int na = local_dofs(a, la), nb = local_dofs(b, lb);
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < na; ++i) f(la[i], lb[j]);
    }
  };
  const auto stencil_entries = [&](bool core, const std::vector<int>& v, auto&& f) {
    const int K = static_cast<int>(v.size());
    if (!core) {
      for (int j = 0; j < 3 * K; ++j) {
        for (int i = 0; i < 3 * K; ++i) {
          f(map.dof(3 * v[static_cast<std::size_t>(i / 3)] + i % 3), map.dof(3 * v[static_cast<std::size_t>(j / 3)] + j % 3));
        }
      }
      return;
    }
    for (int b = 0; b < K; ++b) {
      for (int a = 0; a < K; ++a) block_entries(v[static_cast<std::size_t>(a)], v[static_cast<std::size_t>(b)], f);
    }
  };

  // Pass 1: the pattern.
  std::vector<Eigen::Triplet<double>> trip;
  const auto lower = [&](int r, int c) {
    if (r >= 0 && c >= 0 && r >= c) trip.emplace_back(r, c, 0.0);
  };
  for_each_entry([&](std::size_t, Eigen::Index, bool core, const std::vector<int>& v) { stencil_entries(core, v, lower); },
                 [&](int a, int b) { block_entries(a, b, lower); });
  for (int j = 0; j < nc; ++j) {
    for (int i = j; i < nc; ++i) lower(static_cast<int>(map.num_vertex_dofs()) + i, static_cast<int>(map.num_vertex_dofs()) + j);
  }
  for (Eigen::Index d = 0; d < n; ++d) lower(static_cast<int>(d), static_cast<int>(d));
  pattern_.resize(n, n);
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  trip.clear();
  trip.shrink_to_fit();

  // Pass 2: the slots.
  const auto slot = [&](int r, int c) { return r >= 0 && c >= 0 && r >= c ? lower_slot(pattern_, r, c) : -1; };
  const auto push = [&](int r, int c) { slots_.push_back(slot(r, c)); };
  stencils_.clear();
  for (const Term* t : terms_) {
    if (t->stencil_size() == 0) continue;
    Stencils s;
    s.term = t;
    s.size = t->stencil_size();
    s.offset.reserve(static_cast<std::size_t>(t->num_stencils()));
    s.on_core.reserve(static_cast<std::size_t>(t->num_stencils()));
    stencils_.push_back(std::move(s));
  }
  vertex_offset_.assign(static_cast<std::size_t>(nv), -1);
  std::size_t current = 0;
  const Term* current_term = nullptr;
  for_each_entry(
      [&](std::size_t ti, Eigen::Index, bool core, const std::vector<int>& v) {
        if (terms_[ti] != current_term) {
          current_term = terms_[ti];
          current = static_cast<std::size_t>(std::find_if(stencils_.begin(), stencils_.end(),
                                                          [&](const Stencils& s) { return s.term == current_term; }) -
                                             stencils_.begin());
        }
        Stencils& st = stencils_[current];
        st.offset.push_back(static_cast<std::int64_t>(slots_.size()));
        st.on_core.push_back(core ? 1 : 0);
        stencil_entries(core, v, push);
      },
      [&](int a, int b) {
        const auto at = static_cast<std::int64_t>(slots_.size());
        if (a == b) {
          vertex_offset_[static_cast<std::size_t>(a)] = at;
        } else {
          pair_offset_[pair_key(a, b)] = at;
        }
        block_entries(a, b, push);
      });
  diagonal_slots_.resize(static_cast<std::size_t>(n));
  for (Eigen::Index d = 0; d < n; ++d) diagonal_slots_[static_cast<std::size_t>(d)] = slot(static_cast<int>(d), static_cast<int>(d));
  core_slots_.resize(static_cast<std::size_t>(nc * nc));
  const auto base = static_cast<int>(map.num_vertex_dofs());
  for (int j = 0; j < nc; ++j) {
    for (int i = 0; i < nc; ++i) core_slots_[static_cast<std::size_t>(i + nc * j)] = slot(base + i, base + j);
  }
}

bool Assembler::extend(const Term* term) {
  if (term->stencil_size() != 0) return false;
  std::vector<std::array<int, 2>> fresh;
  for (const auto& [a, b] : term->vertex_pairs()) {
    if (a == b) continue;
    for (const std::array<int, 2> p : {std::array<int, 2>{a, b}, std::array<int, 2>{b, a}}) {
      if (!pair_offset_.count(pair_key(p[0], p[1]))) fresh.push_back(p);
    }
  }
  std::sort(fresh.begin(), fresh.end());
  fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
  std::vector<int> slots;
  for (const auto& [a, b] : fresh) {
    int la[6], lb[6];
    const int na = local_dofs(a, la), nb = local_dofs(b, lb);
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < na; ++i) {
        const int r = la[i], c = lb[j];
        const bool wanted = r >= 0 && c >= 0 && r >= c;
        const int s = wanted ? lower_slot(pattern_, r, c) : -1;
        if (wanted && s < 0) return false;
        slots.push_back(s);
      }
    }
  }
  std::size_t k = 0;
  for (const auto& [a, b] : fresh) {
    pair_offset_[pair_key(a, b)] = static_cast<std::int64_t>(slots_.size());
    int la[6];
    const int n = local_dofs(a, la) * local_dofs(b, la);
    slots_.insert(slots_.end(), slots.begin() + static_cast<std::ptrdiff_t>(k),
                  slots.begin() + static_cast<std::ptrdiff_t>(k + static_cast<std::size_t>(n)));
    k += static_cast<std::size_t>(n);
  }
  terms_.push_back(term);
  return true;
}

std::vector<Assembler::CoreJacobian> Assembler::core_jacobians(const Eigen::VectorXd& x) const {
  std::vector<CoreJacobian> out;
  if (!map_->has_core()) return out;
  const DofMap::Frame f = map_->frame(x);
  const std::vector<int>& attached = map_->core().attached;
  out.resize(attached.size(), CoreJacobian(3, map_->num_core_dofs()));
  for (std::size_t i = 0; i < attached.size(); ++i) map_->core_jacobian(f, attached[i], out[i]);
  return out;
}

void Assembler::scatter(const std::vector<CoreJacobian>& jacobians, int a, int b, const Eigen::Matrix3d& K,
                        const int* slots, double* values) const {
  const int ia = attached_index_[static_cast<std::size_t>(a)], ib = attached_index_[static_cast<std::size_t>(b)];
  if (ia < 0 && ib < 0) {
    for (int k = 0; k < 9; ++k) {
      if (slots[k] >= 0) values[slots[k]] += K.data()[k];
    }
    return;
  }
  using Local = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 6, 6>;
  Local R;
  if (ia >= 0 && ib >= 0) {
    R = jacobians[static_cast<std::size_t>(ia)].transpose() * K * jacobians[static_cast<std::size_t>(ib)];
  } else if (ia >= 0) {
    R = jacobians[static_cast<std::size_t>(ia)].transpose() * K;
  } else {
    R = K * jacobians[static_cast<std::size_t>(ib)];
  }
  for (Eigen::Index k = 0; k < R.size(); ++k) {
    if (slots[k] >= 0) values[slots[k]] += R.data()[k];
  }
}

void Assembler::assemble(const Eigen::VectorXd& x, const VertexState& s, PsdProjection projection,
                         Eigen::SparseMatrix<double>& H) const {
  if (H.rows() != pattern_.rows() || H.nonZeros() != pattern_.nonZeros() || !H.isCompressed() ||
      !std::equal(H.innerIndexPtr(), H.innerIndexPtr() + H.nonZeros(), pattern_.innerIndexPtr()) ||
      !std::equal(H.outerIndexPtr(), H.outerIndexPtr() + H.outerSize() + 1, pattern_.outerIndexPtr())) {
    H = pattern_;
  }
  std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
  double* values = H.valuePtr();
  const std::vector<CoreJacobian> jacobians = core_jacobians(x);

  std::vector<double> buffer;
  std::vector<int> vertices;
  for (const Stencils& st : stencils_) {
    // Room for the largest stencil; stencil i's Hessian is (3K_i)², K_i ≤ K.
    const Eigen::Index m = 3 * st.size;
    const Eigen::Index count = st.term->num_stencils();
    const Eigen::Index chunk = std::clamp(kBuffer / (m * m), Eigen::Index{1}, kChunk);
    buffer.resize(static_cast<std::size_t>(std::min(count, chunk) * m * m));
    vertices.resize(static_cast<std::size_t>(st.size));
    for (Eigen::Index begin = 0; begin < count; begin += chunk) {
      const Eigen::Index end = std::min(count, begin + chunk);
      std::atomic<bool> admissible{true};
      tbb::parallel_for(tbb::blocked_range<Eigen::Index>(begin, end, kGrain), [&](const auto& range) {
        for (Eigen::Index i = range.begin(); i != range.end(); ++i) {
          if (!st.term->stencil_hessian(s, i, projection, buffer.data() + (i - begin) * m * m)) {
            admissible = false;
            return;
          }
        }
      });
      if (!admissible) throw Error(ErrorKind::Internal, "Hessian requested at an inverted configuration");
      for (Eigen::Index i = begin; i < end; ++i) {
        const double* h = buffer.data() + (i - begin) * m * m;
        const int* slots = slots_.data() + st.offset[static_cast<std::size_t>(i)];
        const int K = st.term->stencil(i, vertices.data());
        const Eigen::Index mi = 3 * K;
        if (!st.on_core[static_cast<std::size_t>(i)]) {
          for (Eigen::Index k = 0; k < mi * mi; ++k) {
            if (slots[k] >= 0) values[slots[k]] += h[k];
          }
          continue;
        }
        const Eigen::Map<const Eigen::MatrixXd> hm(h, mi, mi);
        int la[6];
        for (int b = 0; b < K; ++b) {
          for (int a = 0; a < K; ++a) {
            const int va = vertices[static_cast<std::size_t>(a)], vb = vertices[static_cast<std::size_t>(b)];
            scatter(jacobians, va, vb, hm.block<3, 3>(3 * a, 3 * b), slots, values);
            slots += local_dofs(va, la) * local_dofs(vb, la);
          }
        }
      }
    }
  }

  std::vector<VertexBlock> blocks;
  for (const Term* t : terms_) {
    blocks.clear();
    t->add_blocks(s, projection, blocks);
    for (const VertexBlock& b : blocks) {
      std::int64_t at = -1;
      if (b.row == b.col) {
        at = vertex_offset_[static_cast<std::size_t>(b.row)];
      } else {
        const auto it = pair_offset_.find(pair_key(b.row, b.col));
        if (it == pair_offset_.end()) {
          throw Error(ErrorKind::Internal,
                      fmt::format("a term adds a block on vertices {} and {}, a pair it did not name", b.row, b.col));
        }
        at = it->second;
      }
      scatter(jacobians, b.row, b.col, b.block, slots_.data() + at, values);
    }
  }
}

void Assembler::add_vertex_mass(const Eigen::VectorXd& x, const Eigen::VectorXd& m, double scale,
                                Eigen::SparseMatrix<double>& H) const {
  const std::vector<CoreJacobian> jacobians = core_jacobians(x);
  double* values = H.valuePtr();
  for (Eigen::Index v = 0; v < m.size(); ++v) {
    const int* slots = slots_.data() + vertex_offset_[static_cast<std::size_t>(v)];
    if (!map_->attached(v)) {
      for (int c = 0; c < 3; ++c) {
        if (slots[4 * c] >= 0) values[slots[4 * c]] += scale * m[v];
      }
      continue;
    }
    scatter(jacobians, static_cast<int>(v), static_cast<int>(v), (scale * m[v]) * Eigen::Matrix3d::Identity(), slots,
            values);
  }
}

void Assembler::add_diagonal(const Eigen::VectorXd& d, double scale, Eigen::SparseMatrix<double>& H) const {
  double* values = H.valuePtr();
  for (Eigen::Index k = 0; k < d.size(); ++k) {
    if (d[k] != 0.0) values[diagonal_slots_[static_cast<std::size_t>(k)]] += scale * d[k];
  }
}

void Assembler::add_rotation_block(const Eigen::Matrix3d& c, Eigen::SparseMatrix<double>& H) const {
  const std::vector<int>& dofs = map_->core_dofs();
  const auto nc = static_cast<int>(dofs.size());
  double* values = H.valuePtr();
  for (int j = 0; j < nc; ++j) {
    for (int i = 0; i < nc; ++i) {
      const int a = dofs[static_cast<std::size_t>(i)], b = dofs[static_cast<std::size_t>(j)];
      const int slot = core_slots_[static_cast<std::size_t>(i + nc * j)];
      if (a >= 3 && b >= 3 && slot >= 0) values[slot] += c(a - 3, b - 3);
    }
  }
}

}  // namespace palpa
