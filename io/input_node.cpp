// Typed, located access to YAML input with one-line error messages.
#include "io/input_node.hpp"

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>

namespace latticedyn {

namespace {
std::string location(const std::string& file, int line, int column) {
  std::ostringstream os;
  os << file << ":" << line << ":" << column;
  return os.str();
}
std::string join(std::initializer_list<const char*> items) {
  std::string out;
  for (const char* s : items) out += (out.empty() ? "" : ", ") + std::string(s);
  return out;
}
}  // namespace

InputError::InputError(const std::string& file, int line, int column, const std::string& key, const std::string& message)
    : std::runtime_error(location(file, line, column) + ": " + (key.empty() ? "" : key + ": ") + message),
      file_(file),
      line_(line),
      column_(column),
      key_(key) {}

InputNode::InputNode(YAML::Node node, std::string path, std::shared_ptr<const std::string> file)
    : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)) {}

InputNode& InputNode::operator=(const InputNode& o) {
  if (this != &o) {
    node_.reset(o.node_);
    path_ = o.path_;
    file_ = o.file_;
    key_files_ = o.key_files_;
  }
  return *this;
}

namespace {

// Every key of every map a scalar: yaml-cpp accepts lists and maps as keys ([a]: 1), which no
// model key can be, and converting one to text would throw far from its line.
// An alias (*name) is its anchor's node again: a node that contains itself (a: &a [*a]) would
// make this walk, and every reader after it, recurse without end, and anchors that each list the
// one before twice make a few hundred bytes billions of nodes. So the document, its aliases
// followed, is limited in depth and in nodes; no document without aliases comes near either.
constexpr int kMaxDepth = 200;
constexpr std::size_t kMaxNodesBase = 100000, kMaxNodesPerByte = 4;

void check_node(const YAML::Node& n, const std::string& path, std::size_t& nodes_left, int depth) {
  if (depth > kMaxDepth || nodes_left-- == 0) {
    const YAML::Mark m = n.Mark();
    throw InputError(path, m.line >= 0 ? m.line + 1 : 1, m.column >= 0 ? m.column + 1 : 1, "",
                     depth > kMaxDepth ? "nested more than " + std::to_string(kMaxDepth) +
                                             " levels deep (or an alias *name inside its own anchor &name)"
                                       : "the aliases (*name) expand the document to too many nodes");
  }
  if (n.IsMap()) {
    for (auto it = n.begin(); it != n.end(); ++it) {
      if (!it->first.IsScalar()) {
        const YAML::Mark m = it->first.Mark();
        throw InputError(path, m.line + 1, m.column + 1, "", "a key must be a plain name, not a list or a map");
      }
      check_node(it->second, path, nodes_left, depth + 1);
    }
  } else if (n.IsSequence()) {
    for (const YAML::Node& item : n) check_node(item, path, nodes_left, depth + 1);
  }
}

void check_keys(const YAML::Node& root, const std::string& path, std::uintmax_t bytes) {
  std::size_t nodes_left = kMaxNodesBase + kMaxNodesPerByte * static_cast<std::size_t>(bytes);
  check_node(root, path, nodes_left, 0);
}

YAML::Node parse_file(const std::string& path) {
  // Only regular files: a directory, a FIFO or a device would fail late or block without end.
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(path, 0, 0, "", "cannot open the model file (no such file)");
  if (!std::filesystem::is_regular_file(status))
    throw InputError(path, 0, 0, "", "the model must be a regular file (this is a directory, a pipe or a device)");
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > kMaxModelFileBytes)
    throw InputError(path, 0, 0, "",
                     "the model file has " + std::to_string(bytes) + " bytes, more than the limit of " +
                         std::to_string(kMaxModelFileBytes));
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path, 0, 0, "", "cannot open the model file");
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, e.mark.column + 1, "", "YAML syntax error: " + e.msg);
  }
  check_keys(root, path, ec ? 0 : bytes);
  return root;
}

}  // namespace

InputNode InputNode::load_file(const std::string& path) {
  auto file = std::make_shared<const std::string>(path);
  InputNode top(parse_file(path), "", file);
  if (!top.node_.IsMap() || !top.node_["base"]) return top;
  // Follow the chain of bases; a key of a later file replaces the same key of its base.
  std::vector<InputNode> chain{top};
  // Error codes, not exceptions: a name too long for the file system is a bad input like any other.
  auto canonical = [](const std::filesystem::path& p) {
    std::error_code ec;
    const std::filesystem::path c = std::filesystem::weakly_canonical(p, ec);
    return ec ? p.lexically_normal().string() : c.string();
  };
  std::set<std::string> seen{canonical(path)};
  while (chain.back().node_.IsMap() && chain.back().node_["base"]) {
    const InputNode link = chain.back()["base"];
    const std::filesystem::path from = std::filesystem::path(link.file()).parent_path() / link.as_string();
    if (!seen.insert(canonical(from)).second) link.fail("'" + from.string() + "' is already a base of this file (a cycle)");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(from, ec))
      link.fail("no model file '" + from.string() + "'" + (ec && ec != std::errc::no_such_file_or_directory ? " (" + ec.message() + ")" : ""));
    chain.push_back(InputNode(parse_file(from.string()), "", std::make_shared<const std::string>(from.string())));
    if (!chain.back().node_.IsMap()) chain.back().fail("expected a map of keys (a model file)");
  }
  YAML::Node merged(YAML::NodeType::Map);
  auto files = std::make_shared<KeyFiles>();
  std::set<std::string> taken;
  for (const InputNode& layer : chain)  // from this file down to the last base: first one wins
    for (auto it = layer.node_.begin(); it != layer.node_.end(); ++it) {
      const std::string key = it->first.as<std::string>();
      if (key == "base" || !taken.insert(key).second) continue;
      merged.force_insert(it->first, it->second);
      (*files)[key] = layer.file_;
    }
  InputNode root(merged, "", file);
  root.key_files_ = std::move(files);
  return root;
}

namespace {

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::string part;
  for (char c : path) {
    if (c == '.') {
      parts.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  parts.push_back(part);
  return parts;
}

// The item of a list named by `key`: an item whose `name` is `key`, else the index `key`.
std::optional<std::size_t> find_item(const YAML::Node& list, const std::string& key) {
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].IsMap() && list[i]["name"] && list[i]["name"].IsScalar() && list[i]["name"].Scalar() == key) return i;
  // An index: digits, fewer than a list could have as items (std::stoul would throw beyond 2^64).
  if (!key.empty() && key.size() <= 9 && key.find_first_not_of("0123456789") == std::string::npos) {
    const std::size_t i = std::stoul(key);
    if (i < list.size()) return i;
  }
  return std::nullopt;
}

void apply_override(YAML::Node root, const KeyOverride& o, const std::string& model_file) {
  const auto parts = split_path(o.path);
  auto fail = [&](const std::string& what) {
    throw InputError(o.origin_file, o.origin_line, o.origin_column, "", "override '" + o.path + "' of " + model_file + ": " + what);
  };
  YAML::Node at;
  at.reset(root);
  std::string walked;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::string& key = parts[k];
    if (key.empty()) fail("empty key in the path");
    const bool last = k + 1 == parts.size();
    const std::string where = walked.empty() ? "the model" : "'" + walked + "'";
    if (at.IsSequence()) {
      const auto i = find_item(at, key);
      if (!i) fail(where + " is a list without an item named '" + key + "'");
      if (last) {
        at[*i] = o.value;
        return;
      }
      YAML::Node next = at[*i];
      at.reset(next);
    } else if (at.IsMap()) {
      if (last) {
        at[key] = o.value;  // replaces the value, or adds the key to an existing map
        return;
      }
      if (!at[key]) fail(where + " has no key '" + key + "'");
      YAML::Node next = at[key];
      at.reset(next);
    } else {
      fail(where + " is a single value, not a map or list with '" + key + "'");
    }
    walked += (walked.empty() ? "" : ".") + key;
  }
}

}  // namespace

KeyOverride make_key_override(const std::string& path, const YAML::Node& value, const InputNode& at) {
  KeyOverride o;
  o.path = path;
  o.value = value;
  o.origin_file = at.file();
  o.origin_line = at.line();
  o.origin_column = at.column();
  return o;
}

std::optional<InputNode> InputNode::at_path(const std::string& dotted) const {
  InputNode at = *this;
  for (const std::string& key : split_path(dotted)) {
    if (at.node_.IsSequence()) {
      const auto i = find_item(at.node_, key);
      if (!i) return std::nullopt;
      at = at.items()[*i];
    } else if (at.has(key)) {
      at = at[key];
    } else {
      return std::nullopt;
    }
  }
  return at;
}

InputNode InputNode::load_file(const std::string& path, const std::vector<KeyOverride>& overrides) {
  InputNode root = load_file(path);
  if (!overrides.empty() && !root.node_.IsMap()) root.fail("expected a map of keys (a model file)");
  for (const KeyOverride& o : overrides) apply_override(root.node_, o, path);
  return root;
}

std::shared_ptr<const std::string> InputNode::file_of(const std::string& key) const {
  if (key_files_) {
    const auto it = key_files_->find(key);
    if (it != key_files_->end()) return it->second;
  }
  return file_;
}

InputNode InputNode::load_string(const std::string& text, const std::string& name) {
  auto file = std::make_shared<const std::string>(name);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(name, e.mark.line + 1, e.mark.column + 1, "", "YAML syntax error: " + e.msg);
  }
  check_keys(root, name, text.size());
  return InputNode(root, "", file);
}

InputNode InputNode::load_string(const std::string& text, const std::string& name,
                                 const std::vector<KeyOverride>& overrides) {
  InputNode root = load_string(text, name);
  if (!overrides.empty() && !root.node_.IsMap()) root.fail("expected a map of keys (a model file)");
  for (const KeyOverride& o : overrides) apply_override(root.node_, o, name);
  return root;
}

void InputNode::fail(const std::string& message) const {
  const YAML::Mark m = node_.Mark();
  // A node built without position (e.g. an empty document) reports line 1.
  throw InputError(*file_, m.line >= 0 ? m.line + 1 : 1, m.column >= 0 ? m.column + 1 : 1, path_, message);
}

InputNode InputNode::child(const YAML::Node& n, const std::string& key) const {
  return InputNode(n, path_.empty() ? key : path_ + "." + key, file_of(key));
}

void InputNode::allow_only(std::initializer_list<const char*> allowed) const {
  if (!node_.IsMap()) fail("expected a map of keys");
  // Every model item passes here: no allocation per key unless one is wrong (a million-unknown
  // lattice has a few million keys).
  std::vector<bool> seen(allowed.size(), false);
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string& key = it->first.Scalar();
    const auto at = [&] { return InputNode(it->first, path_.empty() ? key : path_ + "." + key, file_of(key)); };
    std::size_t index = 0;
    for (const char* a : allowed) {
      if (key == a) break;
      ++index;
    }
    if (index == allowed.size()) at().fail("unknown key '" + key + "' (expected one of: " + join(allowed) + ")");
    if (seen[index]) at().fail("key '" + key + "' appears twice");
    seen[index] = true;
  }
}

namespace {

// The value of `key` in `map` if the map has it with a value (a key written without one, `key:`,
// counts as absent); one lookup, as yaml-cpp searches a map key by key.
std::optional<YAML::Node> present_value(const YAML::Node& map, const std::string& key) {
  if (!map.IsMap()) return std::nullopt;
  YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) return std::nullopt;
  return n;
}

}  // namespace

bool InputNode::has(const std::string& key) const { return present_value(node_, key).has_value(); }

InputNode InputNode::operator[](const std::string& key) const {
  if (!node_.IsMap()) fail("expected a map with key '" + key + "'");
  const auto n = present_value(node_, key);
  if (!n) fail("missing required key '" + key + "'");
  return child(*n, key);
}

std::optional<InputNode> InputNode::get(const std::string& key) const {
  const auto n = present_value(node_, key);
  if (!n) return std::nullopt;
  return child(*n, key);
}

std::vector<InputNode> InputNode::items() const {
  if (!node_.IsSequence()) fail("expected a list");
  std::vector<InputNode> out;
  for (std::size_t i = 0; i < node_.size(); ++i)
    out.push_back(InputNode(node_[i], path_ + "[" + std::to_string(i) + "]", file_));
  return out;
}

std::vector<std::pair<std::string, InputNode>> InputNode::entries() const {
  if (!node_.IsMap()) fail("expected a map");
  std::vector<std::pair<std::string, InputNode>> out;
  std::set<std::string> seen;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string key = it->first.as<std::string>();
    if (!seen.insert(key).second) InputNode(it->first, path_ + "." + key, file_).fail("key '" + key + "' appears twice");
    out.emplace_back(key, child(it->second, key));
  }
  return out;
}

std::string InputNode::as_string() const {
  if (!node_.IsScalar()) fail("expected a text value");
  return node_.Scalar();
}

bool InputNode::as_bool() const {
  bool b = false;
  if (!node_.IsScalar() || !YAML::convert<bool>::decode(node_, b)) fail("expected true or false, got '" + node_.Scalar() + "'");
  return b;
}

int InputNode::as_int() const {
  int i = 0;
  if (!node_.IsScalar() || !YAML::convert<int>::decode(node_, i)) fail("expected a whole number, got '" + node_.Scalar() + "'");
  return i;
}

double InputNode::as_double() const {
  double d = 0;
  if (!node_.IsScalar() || !YAML::convert<double>::decode(node_, d) || !std::isfinite(d))
    fail("expected a finite number, got '" + (node_.IsScalar() ? node_.Scalar() : std::string("a list or map")) + "'");
  return d;
}

double InputNode::as_positive() const {
  const double d = as_double();
  if (!(d > 0)) fail("expected a positive number, got " + node_.Scalar());
  return d;
}

double InputNode::as_non_negative() const {
  const double d = as_double();
  if (d < 0) fail("expected a number >= 0, got " + node_.Scalar());
  return d;
}

std::vector<double> InputNode::as_doubles() const {
  std::vector<double> out;
  for (const InputNode& n : items()) out.push_back(n.as_double());
  return out;
}

Vec3 InputNode::as_vec3() const {
  if (!node_.IsSequence() || node_.size() != 3) fail("expected a list of 3 numbers [x, y, z]");
  const auto v = as_doubles();
  return Vec3(v[0], v[1], v[2]);
}

Mat3 InputNode::as_mat3() const {
  const auto rows = items();
  if (rows.size() != 3) fail("expected 3 rows of 3 numbers");
  Mat3 m;
  for (int i = 0; i < 3; ++i) m.row(i) = rows[i].as_vec3().transpose();
  return m;
}

std::string InputNode::as_choice(std::initializer_list<const char*> choices) const {
  const std::string s = as_string();
  for (const char* c : choices)
    if (s == c) return s;
  fail("'" + s + "' is not one of: " + join(choices));
}

namespace {

// The value of an optional key, read by `as`, or the fallback: the key is looked up once (get), not
// by has() and then operator[].
template <class T, class As>
T value_or(const std::optional<InputNode>& node, const T& fallback, As as) {
  return node ? ((*node).*as)() : fallback;
}

}  // namespace

double InputNode::get_double(const std::string& key, double fallback) const {
  return value_or(get(key), fallback, &InputNode::as_double);
}
double InputNode::get_positive(const std::string& key, double fallback) const {
  return value_or(get(key), fallback, &InputNode::as_positive);
}
double InputNode::get_non_negative(const std::string& key, double fallback) const {
  return value_or(get(key), fallback, &InputNode::as_non_negative);
}
int InputNode::get_int(const std::string& key, int fallback) const { return value_or(get(key), fallback, &InputNode::as_int); }
bool InputNode::get_bool(const std::string& key, bool fallback) const {
  return value_or(get(key), fallback, &InputNode::as_bool);
}
std::string InputNode::get_string(const std::string& key, const std::string& fallback) const {
  return value_or(get(key), fallback, &InputNode::as_string);
}
Vec3 InputNode::get_vec3(const std::string& key, const Vec3& fallback) const {
  return value_or(get(key), fallback, &InputNode::as_vec3);
}

}  // namespace latticedyn
