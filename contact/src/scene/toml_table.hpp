// Reading a scene file (contact/src/scene/scene_file.cpp): a TOML table that names the
// key in every error, and the accepted interval of each number with its unit.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <toml.hpp>
#include <vector>

#include "contact/scene.hpp"
#include "text_format.hpp"

namespace contact::internal {

/// Integers in full (4294967297, not 4.29497e+09), other numbers with 6 digits.
inline std::string Str(double x) {
  if (x == std::floor(x) && std::abs(x) < 1e15)
    return std::to_string(static_cast<long long>(x));
  return internal::FormatShort(x);
}

/// The accepted interval of a scene number and its SI unit: every number of a scene is
/// read through one of these, so a new key gets its range check and its one-line message
/// "file:line: 'table.key' = value unit is outside the accepted range [min, max] unit".
/// The bounds keep every derived quantity (stiffness E/h^2, omega_max^2 = E/(rho h^2),
/// step counts) finite in double precision; they are far outside any physical use.
struct Range {
  double min, max;
  const char* unit;
  bool min_open = false, max_open = false;  ///< "(" or ")" instead of "[" or "]"
  bool Contains(double x) const {
    return (min_open ? x > min : x >= min) && (max_open ? x < max : x <= max);
  }
  std::string Describe() const {
    const std::string u = unit[0] ? std::string(" ") + unit : "";
    return std::string(" the accepted range ") + (min_open ? "(" : "[") + Str(min) +
           ", " + Str(max) + (max_open ? ")" : "]") + u;
  }
};
/// A TOML table that remembers which keys were read, so that unknown keys (typos) can be
/// reported by name, and that names the key in every error.
class Table {
 public:
  Table(const toml::value* value, std::string path, std::string file)
      : value_(value), path_(std::move(path)), file_(std::move(file)) {}

  bool Has(const std::string& key) const {
    return value_ != nullptr && value_->as_table().count(key) > 0;
  }

  const toml::value& Get(const std::string& key) const {
    used_.insert(key);
    if (!Has(key)) Fail(key, "is missing" + TypoHint(key));
    return value_->as_table().at(key);
  }

  /// A number in `range` (integers are accepted and converted exactly when |n| < 2^53).
  double Number(const std::string& key, const Range& range) const {
    const toml::value& v = Get(key);
    const double x = ToDouble(key, v, v, range);
    CheckRange(key, x, range, v);
    return x;
  }
  double Number(const std::string& key, const Range& range, double fallback) const {
    return Has(key) ? Number(key, range) : (used_.insert(key), fallback);
  }
  /// An integer in [range.min, range.max], checked on the 64-bit value before narrowing.
  int Integer(const std::string& key, const Range& range, int fallback) const {
    if (!Has(key)) return used_.insert(key), fallback;
    const toml::value& v = Get(key);
    if (!v.is_integer())
      Fail(key, "must be an integer in" + range.Describe() + Got(v), &v);
    const double x = ToDouble(key, v, v, range);
    CheckRange(key, x, range, v);
    return static_cast<int>(v.as_integer());
  }
  bool Boolean(const std::string& key, bool fallback) const {
    if (!Has(key)) return used_.insert(key), fallback;
    const toml::value& v = Get(key);
    if (!v.is_boolean()) Fail(key, "must be true or false" + Got(v), &v);
    return v.as_boolean();
  }
  std::string String(const std::string& key) const {
    const toml::value& v = Get(key);
    if (!v.is_string()) Fail(key, "must be a string" + Got(v), &v);
    return v.as_string().str;
  }
  std::string String(const std::string& key, const std::string& fallback) const {
    return Has(key) ? String(key) : (used_.insert(key), fallback);
  }
  /// One of `choices`.
  std::string Choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& fallback = "") const {
    const std::string s =
        fallback.empty() || Has(key) ? String(key) : (used_.insert(key), fallback);
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
      std::string list;
      for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
      Fail(key, "must be one of " + list + ", got \"" + s + "\"", &Get(key));
    }
    return s;
  }
  /// An array of numbers, each in `range` (and `expected_size` entries if >= 0).
  std::vector<double> Numbers(const std::string& key, const Range& range,
                              int expected_size = -1) const {
    const toml::value& v = Get(key);
    if (!v.is_array())
      Fail(key, "must be an array of numbers in" + range.Describe() + Got(v), &v);
    if (expected_size >= 0 && static_cast<int>(v.as_array().size()) != expected_size)
      Fail(key,
           "must have " + std::to_string(expected_size) + " entries, got " +
               std::to_string(v.as_array().size()),
           &v);
    std::vector<double> out;
    for (const toml::value& e : v.as_array()) {
      out.push_back(ToDouble(key, e, v, range));
      CheckRange(key, out.back(), range, v, out.size() - 1);
    }
    return out;
  }
  Eigen::VectorXd Vec(const std::string& key, const Range& range, int size) const {
    const std::vector<double> v = Numbers(key, range, size);
    return Eigen::Map<const Eigen::VectorXd>(v.data(),
                                             static_cast<Eigen::Index>(v.size()));
  }
  std::vector<std::string> Strings(const std::string& key) const {
    if (!Has(key)) return used_.insert(key), std::vector<std::string>{};
    const toml::value& v = Get(key);
    if (!v.is_array()) Fail(key, "must be an array of strings", &v);
    std::vector<std::string> out;
    for (const toml::value& e : v.as_array()) {
      if (!e.is_string()) Fail(key, "must be an array of strings", &v);
      out.push_back(e.as_string().str);
    }
    return out;
  }
  Table Sub(const std::string& key, bool required) const {
    if (!Has(key)) {
      if (required) Fail(key, "(a table [" + Join(key) + "]) is missing" + TypoHint(key));
      used_.insert(key);
      return Table(nullptr, Join(key), file_);
    }
    const toml::value& v = Get(key);
    if (!v.is_table()) Fail(key, "must be a table [" + Join(key) + "]", &v);
    return Table(&v, Join(key), file_);
  }
  bool present() const { return value_ != nullptr; }

  /// Throws on keys that were never read.
  void RejectUnknownKeys(const std::string& known_hint = "") const {
    if (value_ == nullptr) return;
    for (const auto& [key, v] : value_->as_table()) {
      if (used_.count(key)) continue;
      std::string known;
      for (const auto& k : used_) known += (known.empty() ? "" : ", ") + k;
      const std::string guess =
          Closest(key, std::vector<std::string>(used_.begin(), used_.end()));
      throw SceneError(
          file_ + ":" + std::to_string(v.location().line()) + ": unknown " +
          (v.is_table() ? "table [" + Join(key) + "]" : "key '" + Join(key) + "'") +
          (guess.empty() ? "" : " - did you mean '" + Join(guess) + "'?") +
          (known.empty() ? "" : " (known keys here: " + known + ")") + known_hint);
    }
  }

  [[noreturn]] void Fail(const std::string& key, const std::string& what,
                         const toml::value* at = nullptr) const {
    // The value's own source: the scene file, or "command line (table.key)" for an
    // override.
    const std::string where =
        at ? at->location().file_name() + ":" + std::to_string(at->location().line())
           : file_;
    throw SceneError(where + ": '" + Join(key) + "' " + what);
  }

 private:
  /// The value of a TOML number as a double. toml11 3.7 saturates an integer literal
  /// beyond the int64 range to INT64_MIN / INT64_MAX without an error, so those two are
  /// refused.
  double ToDouble(const std::string& key, const toml::value& e, const toml::value& at,
                  const Range& range) const {
    if (e.is_floating()) return e.as_floating();
    if (!e.is_integer())
      Fail(key, "must be a number in" + range.Describe() + Got(e), &at);
    const std::int64_t i = e.as_integer();
    if (i == std::numeric_limits<std::int64_t>::max() ||
        i == std::numeric_limits<std::int64_t>::min())
      Fail(key, "is an integer literal beyond the 64-bit range [-2^63, 2^63 - 1]", &at);
    return static_cast<double>(i);
  }
  void CheckRange(const std::string& key, double x, const Range& range,
                  const toml::value& at, size_t entry = static_cast<size_t>(-1)) const {
    if (range.Contains(x)) return;
    const std::string which =
        entry == static_cast<size_t>(-1) ? "" : "entry " + std::to_string(entry) + " ";
    Fail(key,
         which + "= " + Str(x) + (range.unit[0] ? std::string(" ") + range.unit : "") +
             " is outside" + range.Describe(),
         &at);
  }
  static std::string TypeName(const toml::value& v) {
    std::ostringstream s;
    s << v.type();
    return s.str();
  }
  /// ", got a string "2e-5"": the type of a value of the wrong type, and the value itself
  /// when it is a string, a boolean or a number (not a table or array).
  static std::string Got(const toml::value& v) {
    std::string got = ", got a " + TypeName(v);
    if (v.is_string()) return got + " \"" + v.as_string().str + "\"";
    if (v.is_boolean() || v.is_integer() || v.is_floating())
      return got + " " + toml::format(v);
    return got;
  }
  std::string Join(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  /// " (found 'youngs_modulus' in this table: a typo?)" for a present key within edit
  /// distance 2 of the missing one.
  std::string TypoHint(const std::string& missing) const {
    if (value_ == nullptr) return "";
    std::vector<std::string> present;
    for (const auto& entry : value_->as_table()) present.push_back(entry.first);
    const std::string found = Closest(missing, present);
    return found.empty() ? "" : " (found '" + Join(found) + "' instead: a typo?)";
  }
  /// The candidate within edit distance 2 of `word` (the nearest), or "".
  static std::string Closest(const std::string& word,
                             const std::vector<std::string>& candidates) {
    std::string best;
    size_t best_distance = 3;
    for (const std::string& c : candidates) {
      const size_t d = EditDistance(word, c);
      if (d < best_distance) best = c, best_distance = d;
    }
    return best;
  }
  /// Levenshtein distance (insertions, deletions, substitutions).
  static size_t EditDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t above = row[j];
        row[j] = std::min(
            {row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = above;
      }
    }
    return row[b.size()];
  }
  const toml::value* value_;
  std::string path_, file_;
  mutable std::set<std::string> used_;
};

}  // namespace contact::internal
