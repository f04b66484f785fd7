// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/ticks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string_view>

#include "palpa/core/error.hpp"

namespace palpa::report {
namespace {

// Tolerance (in units of one step) when deciding whether a bound sits on a tick.
constexpr double kOnTick = 1e-9;
// Data ranges narrower than this, relative to their magnitude, count as one value.
constexpr double kEqualRelative = 1e-9;
// The number of labelled ticks aimed for, and the fewest wanted when possible.
constexpr int kTargetLabels = 6;
constexpr int kFewestWanted = 5;
// Weight of unused axis length (fraction of the axis) against one tick too many or few.
constexpr double kWasteWeight = 4.0;
// Plain decimals for decimal exponents in [kPlainMinExp, kPlainMaxExp].
constexpr int kPlainMinExp = -3;
constexpr int kPlainMaxExp = 4;
// Log axes with at most this many decades show minor ticks at 2…9 × 10^k.
constexpr int kMinorDecades = 8;
constexpr std::array<int, 3> kNiceMantissas = {1, 2, 5};

// 10^e as a double; exact for |e| <= 22.
double pow10i(int e) {
  return std::pow(10.0, e);
}

// n × 10^e as a double, dividing for negative e so that 3 × 10⁻¹ is the double
// nearest to 0.3.
double decimal_value(long long n, int e) {
  return e >= 0 ? static_cast<double>(n) * pow10i(e) : static_cast<double>(n) / pow10i(-e);
}

std::string superscript(int p) {
  static constexpr std::array<std::string_view, 10> kDigits = {
      "\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
      "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  std::string out;
  if (p < 0) out += "\u207b";
  for (char c : std::to_string(std::abs(p))) out += kDigits[static_cast<std::size_t>(c - '0')];
  return out;
}

// Decimal exponent of the leading digit of n × 10^e (n != 0).
int leading_exponent(long long n, int e) {
  const std::string digits = std::to_string(std::llabs(n));
  return e + static_cast<int>(digits.size()) - 1;
}

bool plain_exponent(int p) {
  return p >= kPlainMinExp && p <= kPlainMaxExp;
}

struct Candidate {
  AxisTicks ticks;
  double score = std::numeric_limits<double>::infinity();
};

// Linear nice ticks on [lo, hi] (lo < hi). fix_lo/fix_hi keep that bound.
AxisTicks linear_ticks(double lo, double hi, bool fix_lo, bool fix_hi, int max_labels) {
  const double range = hi - lo;
  const int e_top = static_cast<int>(std::floor(std::log10(range)));
  Candidate best;
  Candidate fallback;  // fewest ticks above max_labels, when nothing fits
  const int fewest = std::min(kFewestWanted, max_labels);
  const int target = std::min(kTargetLabels, max_labels);
  for (int e = e_top - 3; e <= e_top + 1; ++e) {
    for (int m : kNiceMantissas) {
      const double step = decimal_value(m, e);
      const auto k_lo = static_cast<long long>(fix_lo ? std::ceil(lo / step - kOnTick)
                                                      : std::floor(lo / step + kOnTick));
      const auto k_hi = static_cast<long long>(fix_hi ? std::floor(hi / step + kOnTick)
                                                      : std::ceil(hi / step - kOnTick));
      const long long count = k_hi - k_lo + 1;
      if (count < 1) continue;
      AxisTicks t;
      t.min = fix_lo ? lo : decimal_value(k_lo * m, e);
      t.max = fix_hi ? hi : decimal_value(k_hi * m, e);
      if (!(t.max > t.min)) continue;
      const double waste = 1.0 - range / (t.max - t.min);
      double score = std::abs(static_cast<double>(count - target)) + kWasteWeight * waste;
      if (count < fewest) score += 2.0 * static_cast<double>(fewest - count);
      Candidate* slot = &best;
      if (count > max_labels) {
        slot = &fallback;
        score = static_cast<double>(count);
      }
      if (score >= slot->score) continue;
      // Labels: one form (plain or scientific) for the whole axis, judged by the
      // largest magnitude.
      const long long n_big = std::max(std::llabs(k_lo), std::llabs(k_hi)) * m;
      const bool scientific = n_big != 0 && !plain_exponent(leading_exponent(n_big, e));
      for (long long k = k_lo; k <= k_hi; ++k)
        t.major.push_back({decimal_value(k * m, e), format_decimal(k * m, e, scientific)});
      slot->ticks = std::move(t);
      slot->score = score;
    }
  }
  return std::isfinite(best.score) ? best.ticks : fallback.ticks;
}

// Label of m × 10^p on a log axis: "10ᵖ" for decades in scientific form.
std::string log_label(int m, int p, bool scientific) {
  if (scientific && m == 1) {
    std::string out = "10";
    out.append(superscript(p));
    return out;
  }
  return format_decimal(m, p, scientific);
}

// Log-axis ticks on [lo, hi] (0 < lo < hi).
AxisTicks log_ticks(double lo, double hi, bool fix_lo, bool fix_hi, int max_labels) {
  const double l_lo = std::log10(lo);
  const double l_hi = std::log10(hi);
  constexpr double kFewDecades = 2.0;
  constexpr int kFewestLogLabels = 4;

  if (l_hi - l_lo <= kFewDecades + kOnTick) {
    // 1–2–5 sequence: values m × 10^p.
    struct Value {
      int m, p;
      double v;
    };
    std::vector<Value> seq;
    const int p0 = static_cast<int>(std::floor(l_lo)) - 1;
    const int p1 = static_cast<int>(std::ceil(l_hi)) + 1;
    for (int p = p0; p <= p1; ++p)
      for (int m : kNiceMantissas) seq.push_back({m, p, decimal_value(m, p)});
    const auto on_or_below = [&](double x) {  // largest index with value <= x
      std::size_t i = 0;
      while (i + 1 < seq.size() && seq[i + 1].v <= x * (1 + kOnTick)) ++i;
      return i;
    };
    const auto on_or_above = [&](double x) {  // smallest index with value >= x
      std::size_t i = seq.size() - 1;
      while (i > 0 && seq[i - 1].v >= x * (1 - kOnTick)) --i;
      return i;
    };
    std::size_t i_lo = fix_lo ? on_or_above(lo) : on_or_below(lo);
    std::size_t i_hi = fix_hi ? on_or_below(hi) : on_or_above(hi);
    const int count = i_hi >= i_lo ? static_cast<int>(i_hi - i_lo + 1) : 0;
    if (count >= std::min(kFewestLogLabels, max_labels) && count <= max_labels) {
      AxisTicks t;
      t.log = true;
      t.min = fix_lo ? lo : seq[i_lo].v;
      t.max = fix_hi ? hi : seq[i_hi].v;
      bool scientific = false;
      for (std::size_t i = i_lo; i <= i_hi; ++i) scientific |= !plain_exponent(seq[i].p);
      for (std::size_t i = i_lo; i <= i_hi; ++i)
        t.major.push_back({seq[i].v, log_label(seq[i].m, seq[i].p, scientific)});
      for (int p = seq[i_lo].p - 1; p <= seq[i_hi].p; ++p)
        for (int m = 2; m <= 9; ++m) {
          const double v = decimal_value(m, p);
          if (m != 2 && m != 5 && v > t.min && v < t.max) t.minor.push_back(v);
        }
      return t;
    }
    if (count < std::min(kFewestLogLabels, max_labels)) {
      // Well under a decade: linear nice ticks on the log scale, kept positive.
      AxisTicks t = linear_ticks(lo, hi, fix_lo, fix_hi, max_labels);
      if (!(t.min > 0)) t = linear_ticks(lo, hi, true, fix_hi, max_labels);
      t.log = true;
      return t;
    }
  }

  // Decades, every k-th one.
  const int d_lo =
      static_cast<int>(fix_lo ? std::ceil(l_lo - kOnTick) : std::floor(l_lo + kOnTick));
  const int d_hi =
      static_cast<int>(fix_hi ? std::floor(l_hi + kOnTick) : std::ceil(l_hi - kOnTick));
  int k = 1;
  const auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  const auto ceil_div = [&](int a, int b) { return -floor_div(-a, b); };
  int q_lo = 0, q_hi = 0;
  for (;; ++k) {
    q_lo = fix_lo ? ceil_div(d_lo, k) : floor_div(d_lo, k);
    q_hi = fix_hi ? floor_div(d_hi, k) : ceil_div(d_hi, k);
    if (q_hi - q_lo + 1 <= std::max(max_labels, 2)) break;
  }
  AxisTicks t;
  t.log = true;
  t.min = fix_lo ? lo : pow10i(q_lo * k);
  t.max = fix_hi ? hi : pow10i(q_hi * k);
  bool scientific = false;
  for (int q = q_lo; q <= q_hi; ++q) scientific |= !plain_exponent(q * k);
  for (int q = q_lo; q <= q_hi; ++q)
    t.major.push_back({pow10i(q * k), log_label(1, q * k, scientific)});
  if (k == 1 && d_hi - d_lo <= kMinorDecades) {
    for (int p = d_lo - 1; p <= d_hi; ++p)
      for (int m = 2; m <= 9; ++m) {
        const double v = decimal_value(m, p);
        if (v > t.min && v < t.max) t.minor.push_back(v);
      }
  }
  return t;
}

}  // namespace

std::string format_decimal(long long n, int e, bool scientific) {
  if (n == 0) return "0";
  std::string digits = std::to_string(std::llabs(n));
  while (digits.size() > 1 && digits.back() == '0') {
    digits.pop_back();
    ++e;
  }
  const int len = static_cast<int>(digits.size());
  const int p = e + len - 1;
  // Built by appending only (GCC 12 warns falsely on some string operator+ chains).
  std::string out;
  if (n < 0) out.append("\u2212");
  if (!scientific && plain_exponent(p)) {
    if (e >= 0) {
      out.append(digits).append(static_cast<std::size_t>(e), '0');
    } else if (len + e > 0) {
      const auto point = static_cast<std::size_t>(len + e);
      out.append(digits, 0, point).push_back('.');
      out.append(digits, point);
    } else {
      out.append("0.").append(static_cast<std::size_t>(-(len + e)), '0').append(digits);
    }
    return out;
  }
  out.push_back(digits[0]);
  if (len > 1) out.append(".").append(digits, 1);
  out.append("\u00d710").append(superscript(p));
  return out;
}

AxisTicks choose_ticks(double data_min, double data_max, bool log, std::optional<double> fixed_min,
                       std::optional<double> fixed_max, int max_labels) {
  const char* axis_kind = log ? "log axis" : "axis";
  if (!std::isfinite(data_min) || !std::isfinite(data_max) || data_min > data_max)
    throw_input_error(std::string(axis_kind) + " data range is not a finite interval", {},
                      "finite data_min <= data_max");
  if ((fixed_min && !std::isfinite(*fixed_min)) || (fixed_max && !std::isfinite(*fixed_max)))
    throw_input_error(std::string(axis_kind) + " bound is not finite", {}, "a finite number");
  if (log && (data_min <= 0 || (fixed_min && *fixed_min <= 0) || (fixed_max && *fixed_max <= 0)))
    throw_input_error("log axis has a value or bound <= 0", {}, "positive values on a log axis");
  if (fixed_min && fixed_max && !(*fixed_min < *fixed_max))
    throw_input_error("axis minimum is not below its maximum", {}, "min < max");
  max_labels = std::max(max_labels, 2);

  double lo = fixed_min.value_or(data_min);
  double hi = fixed_max.value_or(data_max);
  const auto width = [&](double a, double b) {
    return log ? std::log10(b / a) : (b - a) / std::max(std::abs(a), std::abs(b));
  };
  if (!(hi > lo) || (!(fixed_min && fixed_max) && width(lo, hi) < kEqualRelative)) {
    const auto pad = [&](double v) { return v != 0 ? 0.5 * std::abs(v) : 1.0; };
    constexpr double kLogPad = 10.0;
    if (fixed_min) {
      hi = log ? lo * kLogPad : lo + pad(lo);
    } else if (fixed_max) {
      lo = log ? hi / kLogPad : hi - pad(hi);
    } else {
      const double v = lo;
      lo = log ? v / kLogPad : v - pad(v);
      hi = log ? v * kLogPad : v + pad(v);
    }
  }
  if (!std::isfinite(hi - lo) || !std::isfinite(hi) || !std::isfinite(lo))
    throw_input_error(std::string(axis_kind) + " range is too large to plot", {},
                      "a range within the double range");
  return log ? log_ticks(lo, hi, fixed_min.has_value(), fixed_max.has_value(), max_labels)
             : linear_ticks(lo, hi, fixed_min.has_value(), fixed_max.has_value(), max_labels);
}

}  // namespace palpa::report
