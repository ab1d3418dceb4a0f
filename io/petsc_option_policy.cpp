// PETSc options from model files: split as PETSc splits them, refused where they reach files.
#include "io/petsc_option_policy.hpp"

#include <array>
#include <cctype>
#include <string_view>

namespace latticedyn {

namespace {

bool is_name(const std::string& token) {
  if (token.size() < 2 || token[0] != '-') return false;
  const char c = token[1] == '-' && token.size() > 2 ? token[2] : token[1];
  return std::isalpha(static_cast<unsigned char>(c)) != 0;  // -1e-6, -.5: numbers
}

bool contains(std::string_view text, std::string_view part) { return text.find(part) != std::string_view::npos; }

// Options that open, write or name files, or start or wait for other processes, whatever their value.
constexpr std::array<std::string_view, 22> kRefusedNames = {
    "options_file", "options_file_yaml", "options_string_yaml", "options_monitor", "log_trace", "history",
    "log_mpe", "log_perfstubs", "malloc_dump", "malloc_view", "memory_view", "on_error_attach_debugger",
    "start_in_debugger", "stop_for_debugger", "debugger_ranks", "debugger_pause", "display", "python",
    "viewer_binary_filename", "viewer_socket_machine", "viewer_socket_port", "info"};

// Options PETSc reads only when it starts, before a model is read: from a model they would fail
// at the end of the run.
constexpr std::array<std::string_view, 6> kStartupOnly = {"log_view", "log_summary", "log_all",
                                                          "malloc_debug", "malloc_test", "fp_trap"};

// Name parts of options that open windows, servers or files of their own.
constexpr std::array<std::string_view, 7> kRefusedParts = {"draw", "_lg", "vtk", "saws", "trajectory", "debugger",
                                                           "matlab"};

// Viewers and monitors take a value [type][:file[:format[:mode]]]; only the terminal is allowed.
bool takes_viewer(std::string_view name) {
  return contains(name, "view") || contains(name, "monitor") || name == "log_summary";
}

std::optional<std::string> refused_viewer(const PetscOptionToken& o) {
  if (o.value.empty()) return std::nullopt;
  const std::string_view v = o.value;
  const std::size_t colon = v.find(':');
  const std::string_view type = v.substr(0, colon);
  if (!type.empty() && type != "ascii" && type != "stdout" && type != "stderr")
    return "-" + o.name + " " + o.value + ": a model's viewers and monitors may print to the terminal only (type '" +
           std::string(type) + "' refused)";
  if (colon != std::string_view::npos) {
    const std::string_view rest = v.substr(colon + 1);
    const std::string_view file = rest.substr(0, rest.find(':'));
    if (!file.empty())
      return "-" + o.name + " " + o.value + ": a model's viewers and monitors may not name a file ('" +
             std::string(file) + "'); give it on the command line";
  }
  return std::nullopt;
}

}  // namespace

std::vector<PetscOptionToken> split_petsc_options(const std::string& options) {
  std::vector<std::string> tokens;
  std::string current;
  bool in_token = false;
  char quote = 0;
  for (const char c : options) {
    if (quote) {
      if (c == quote)
        quote = 0;
      else
        current += c;
    } else if (c == '"' || c == '\'') {
      quote = c;
      in_token = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (in_token) tokens.push_back(current);
      current.clear();
      in_token = false;
    } else {
      current += c;
      in_token = true;
    }
  }
  if (in_token) tokens.push_back(current);

  std::vector<PetscOptionToken> out;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    PetscOptionToken o;
    if (!is_name(tokens[i])) {
      o.value = tokens[i];  // a value without a name: PETSc ignores it, the policy still sees it
      out.push_back(o);
      continue;
    }
    o.name = tokens[i].substr(tokens[i][1] == '-' ? 2 : 1);
    if (i + 1 < tokens.size() && !is_name(tokens[i + 1])) o.value = tokens[++i];
    out.push_back(o);
  }
  return out;
}

std::optional<std::string> refused_model_option(const PetscOptionToken& o) {
  const std::string shown = o.name.empty() ? o.value : "-" + o.name + (o.value.empty() ? "" : " " + o.value);
  for (std::string_view refused : kRefusedNames)
    if (o.name == refused) return shown + ": not allowed in a model file (it reaches files or other processes)";
  for (std::string_view startup : kStartupOnly)
    if (o.name == startup) return shown + ": PETSc reads it only at start-up: give it on the command line";
  for (std::string_view part : kRefusedParts)
    if (contains(o.name, part))
      return shown + ": not allowed in a model file (it opens windows, servers or files of its own)";
  if (o.value.find('/') != std::string::npos)
    return shown + ": a model's options may not hold a path; give it on the command line";
  if (takes_viewer(o.name)) return refused_viewer(o);
  return std::nullopt;
}

}  // namespace latticedyn
