// A YAML node that knows where it stands (file, line, column, key path) and reports every input
// problem as one line "file:line:col: key.path: what was expected", before anything is computed.
#pragma once

#include "core/types.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace latticedyn {

/// The largest model file read (bytes): a 1e6-unknown lattice takes 19 MB.
inline constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{1} << 30;

/// A bad input: carries its location; what() is the complete one-line message.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, int column, const std::string& key, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_, column_;
  std::string key_;
};

/// A value put into a model at a dotted key path before it is read (batch runs, studies):
/// "drives.luffing.value", "solver.static.load_steps", "bodies.load.mass" (a list item by its
/// `name` or its index). The origin (file, line, column) is where the override was written, for
/// error messages.
struct KeyOverride {
  std::string path;
  YAML::Node value;
  std::string origin_file;
  int origin_line = 0;
  int origin_column = 0;
};

class InputNode;

/// The override of `path` by `value`, written at `at` (its origin for error messages).
KeyOverride make_key_override(const std::string& path, const YAML::Node& value, const InputNode& at);

class InputNode {
 public:
  /// Parses a file; a YAML syntax error becomes an InputError with its position. A top-level
  /// `base: other.yaml` (relative to the file) starts from that file: each top-level key of this
  /// file replaces the base's key of the same name entirely; the others come from the base (which
  /// may have a base itself). Errors name the file a key came from.
  static InputNode load_file(const std::string& path);
  /// As load_file, then every override replaces (or, as the last key of an existing map, adds)
  /// the value at its path; a path that leads nowhere is an InputError at the override's origin.
  static InputNode load_file(const std::string& path, const std::vector<KeyOverride>& overrides);
  /// Parses text (for tests), reporting errors against `name`.
  static InputNode load_string(const std::string& text, const std::string& name);
  /// As load_string, then the overrides as in load_file.
  static InputNode load_string(const std::string& text, const std::string& name,
                               const std::vector<KeyOverride>& overrides);

  InputNode(const InputNode&) = default;
  /// Rebinds to the other node. (YAML::Node's own assignment writes into the node it refers to,
  /// which would overwrite the document.)
  InputNode& operator=(const InputNode& o);

  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }
  int line() const { return node_.Mark().line + 1; }
  int column() const { return node_.Mark().column + 1; }
  const YAML::Node& yaml() const { return node_; }
  /// The node at a dotted key path below this one (maps by key, lists by item `name` or index),
  /// if there is one.
  std::optional<InputNode> at_path(const std::string& dotted) const;
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  [[noreturn]] void fail(const std::string& message) const;

  /// The map's keys must be among `allowed` (and appear once); otherwise an error at the key.
  void allow_only(std::initializer_list<const char*> allowed) const;
  bool has(const std::string& key) const;
  InputNode operator[](const std::string& key) const;  ///< required: missing -> error here
  std::optional<InputNode> get(const std::string& key) const;
  std::vector<InputNode> items() const;                         ///< sequence elements
  std::vector<std::pair<std::string, InputNode>> entries() const;  ///< map entries in order

  std::string as_string() const;
  bool as_bool() const;
  int as_int() const;
  double as_double() const;
  double as_positive() const;      ///< > 0
  double as_non_negative() const;  ///< >= 0
  Vec3 as_vec3() const;
  Mat3 as_mat3() const;            ///< 3x3 list of rows
  std::vector<double> as_doubles() const;
  /// One of `choices`; otherwise an error listing them.
  std::string as_choice(std::initializer_list<const char*> choices) const;

  // Convenience: optional keys with defaults.
  double get_double(const std::string& key, double fallback) const;
  double get_positive(const std::string& key, double fallback) const;
  double get_non_negative(const std::string& key, double fallback) const;
  int get_int(const std::string& key, int fallback) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  Vec3 get_vec3(const std::string& key, const Vec3& fallback) const;

 private:
  InputNode(YAML::Node node, std::string path, std::shared_ptr<const std::string> file);
  InputNode child(const YAML::Node& n, const std::string& key) const;
  /// The file a top-level key came from (a `base` merge), else this node's file.
  std::shared_ptr<const std::string> file_of(const std::string& key) const;
  using KeyFiles = std::map<std::string, std::shared_ptr<const std::string>>;

  YAML::Node node_;
  std::string path_;
  std::shared_ptr<const std::string> file_;
  std::shared_ptr<const KeyFiles> key_files_;  // root of a merged file only
};

}  // namespace latticedyn
