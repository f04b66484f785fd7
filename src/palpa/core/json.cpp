// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <set>
#include <vector>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/input_file.hpp"

namespace palpa {

namespace {
std::string type_name(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::string: return "a string";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "a number";
    default: return "an unsupported value";
  }
}

// Watches the parser's events for a key that appears twice in one object
// (the parser itself keeps the last value silently).
class DuplicateKeys {
 public:
  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
        stack_.push_back(Frame{event == E::object_start, {}, {}, 0});
        break;
      case E::key: {
        Frame& f = stack_.back();
        f.last_key = parsed.get<std::string>();
        if (!f.keys.insert(f.last_key).second && key_.empty()) {
          key_ = f.last_key;
          where_ = path();
        }
        break;
      }
      case E::value:
        if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
        break;
      case E::object_end:
      case E::array_end:
        stack_.pop_back();
        break;
    }
    return true;
  }

  const std::string& key() const noexcept { return key_; }
  // The object holding it, as a field path ("" for the top level).
  const std::string& where() const noexcept { return where_; }

 private:
  struct Frame {
    bool object = true;
    std::set<std::string> keys;
    std::string last_key;
    std::size_t index = 0;  // arrays: elements started so far
  };

  std::string path() const {
    std::string p;
    for (std::size_t k = 0; k + 1 < stack_.size(); ++k) {
      const Frame& f = stack_[k];
      if (f.object) {
        p += (p.empty() ? "" : ".") + f.last_key;
      } else {
        p += fmt::format("[{}]", f.index - 1);
      }
    }
    return p;
  }

  std::vector<Frame> stack_;
  std::string key_;
  std::string where_;
};

}  // namespace

Json read_json_file(const std::filesystem::path& path, InputUse use) {
  ErrorContext ctx;
  ctx.file = path.string();
  const std::string text = read_input_file(path, use);
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw_input_error("the file is empty", ctx, "a JSON object");
  }
  try {
    DuplicateKeys duplicates;
    Json j = Json::parse(text, std::ref(duplicates));
    if (!duplicates.key().empty()) {
      throw_input_error(fmt::format("the key \"{}\" appears twice{}", duplicates.key(),
                                    duplicates.where().empty() ? std::string(" at the top level")
                                                               : " in " + duplicates.where()),
                        ctx, "each key once in an object");
    }
    return j;
  } catch (const Json::parse_error& e) {
    // Turn the byte offset into line and column.
    const std::size_t offset = std::min<std::size_t>(e.byte, text.size());
    std::size_t line = 1;
    std::size_t col = 1;
    for (std::size_t i = 0; i + 1 < offset; ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    ctx.line = line;
    ctx.column = col;
    std::string what = e.what();
    const auto pos = what.find("parse error");
    throw_input_error(fmt::format("invalid JSON: {}", pos == std::string::npos ? what : what.substr(pos)),
                      ctx);
  } catch (const Json::exception& e) {
    // The parser's other refusals, such as a number beyond the range of a
    // double ("1e999"): no position is known.
    std::string what = e.what();
    if (const auto end = what.find("] "); end != std::string::npos) what = what.substr(end + 2);
    throw_input_error(fmt::format("invalid JSON: {}", what), ctx, "numbers within the range of a double");
  }
}

namespace {

// The path of the first non-finite number in `j` ("curves[2].force"), or
// nothing.
std::optional<std::string> first_non_finite(const Json& j, const std::string& at) {
  if (j.is_number_float()) {
    if (!std::isfinite(j.get<double>())) return at;
  } else if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      if (auto bad = first_non_finite(value, at.empty() ? key : at + "." + key)) return bad;
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (auto bad = first_non_finite(j[i], fmt::format("{}[{}]", at, i))) return bad;
    }
  }
  return std::nullopt;
}

}  // namespace

std::string format_json(const Json& j, const std::filesystem::path& path) {
  if (const auto bad = first_non_finite(j, "")) {
    ErrorContext ctx;
    ctx.file = path.string();
    ctx.field = fmt::format("field '{}'", *bad);
    throw Error(ErrorKind::Internal, "a value that is not a finite number cannot be written to JSON", ctx);
  }
  return j.dump(2) + '\n';
}

void write_json_file(const std::filesystem::path& path, const Json& j) {
  const std::string text = format_json(j, path);
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

ErrorContext JsonView::context() const {
  ErrorContext ctx;
  ctx.file = file_;
  ctx.field = path_.empty() ? std::string() : fmt::format("field '{}'", path_);
  return ctx;
}

void JsonView::fail(const std::string& problem, const std::string& expected) const {
  throw_input_error(problem, context(), expected);
}

bool JsonView::has(const std::string& key) const { return j_->is_object() && j_->contains(key); }

JsonView JsonView::at(const std::string& key) const {
  if (!j_->is_object()) fail(fmt::format("is {}", type_name(*j_)), "an object");
  const auto it = j_->find(key);
  const std::string child = path_.empty() ? key : path_ + "." + key;
  if (it == j_->end()) {
    ErrorContext ctx;
    ctx.file = file_;
    ctx.field = fmt::format("field '{}'", child);
    throw_input_error("is missing", ctx);
  }
  return JsonView(*it, file_, child);
}

std::optional<JsonView> JsonView::find(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return at(key);
}

JsonView JsonView::at(std::size_t i) const {
  if (!j_->is_array()) fail(fmt::format("is {}", type_name(*j_)), "an array");
  if (i >= j_->size()) fail(fmt::format("has {} elements, no element {}", j_->size(), i));
  return JsonView((*j_)[i], file_, fmt::format("{}[{}]", path_, i));
}

std::size_t JsonView::size() const {
  if (!j_->is_array()) fail(fmt::format("is {}", type_name(*j_)), "an array");
  return j_->size();
}

std::string JsonView::as_string() const {
  if (!j_->is_string()) fail(fmt::format("is {}", type_name(*j_)), "a string");
  return j_->get<std::string>();
}

double JsonView::as_number() const {
  if (!j_->is_number()) fail(fmt::format("is {}", type_name(*j_)), "a number");
  const double v = j_->get<double>();
  if (!std::isfinite(v)) fail("is not finite", "a finite number");
  return v;
}

long long JsonView::as_integer() const {
  if (!j_->is_number_integer()) fail(fmt::format("is {}", type_name(*j_)), "a whole number");
  return j_->get<long long>();
}

bool JsonView::as_bool() const {
  if (!j_->is_boolean()) fail(fmt::format("is {}", type_name(*j_)), "true or false");
  return j_->get<bool>();
}

double JsonView::as_quantity(Dimension d) const {
  if (j_->is_number()) {
    if (d == Dimension::Dimensionless) return as_number();
    fail(fmt::format("the number {} has no unit", j_->dump()), dimension_example(d));
  }
  if (!j_->is_string()) fail(fmt::format("is {}", type_name(*j_)), dimension_example(d));
  return parse_quantity(j_->get<std::string>(), d, context());
}

std::vector<double> JsonView::as_number_array() const {
  const std::size_t n = size();
  std::vector<double> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(at(i).as_number());
  return out;
}

void JsonView::expect_only(const std::vector<std::string>& allowed) const {
  if (!j_->is_object()) fail(fmt::format("is {}", type_name(*j_)), "an object");
  for (const auto& [key, value] : j_->items()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    ErrorContext ctx;
    ctx.file = file_;
    ctx.field = fmt::format("field '{}'", path_.empty() ? key : path_ + "." + key);
    throw_input_error("is not a known field", ctx, fmt::format("one of: {}", list));
  }
}

}  // namespace palpa
