// Copies prefixed options over plain ones in PETSc's options database, and restores them.
#include "timestepping/prefixed_options.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace latticedyn {

namespace {

// latticedyn's own options that share the dynamic prefix.
bool own_option(const std::string& name) {
  return name == "-dyn_dense_below" || name == "-dyn_block_matrix" || name == "-dyn_block_size" || name == "-dyn_predictor";
}

// A token that names an option: a dash and then not a number (-1e-3 is a value).
bool is_name(const std::string& t) {
  return t.size() > 1 && t[0] == '-' && !std::isdigit(static_cast<unsigned char>(t[1])) && t[1] != '.';
}

}  // namespace

PrefixedOptions::PrefixedOptions(const char* prefix) {
  char* all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) != 0 || !all) return;
  std::vector<std::string> tokens;
  std::istringstream in(all);
  for (std::string t; in >> t;) tokens.push_back(t);
  PetscFree(all);
  const std::string lead = std::string("-") + prefix;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const std::string& name = tokens[i];
    if (!is_name(name) || name.rfind(lead, 0) != 0 || name.size() == lead.size() || own_option(name)) continue;
    const bool has_value = i + 1 < tokens.size() && !is_name(tokens[i + 1]);
    const std::string value = has_value ? tokens[i + 1] : "";
    std::string plain = name;
    plain.erase(1, lead.size() - 1);  // -static_snes_rtol -> -snes_rtol
    PetscBool used = PETSC_FALSE;
    PetscOptionsHasName(nullptr, nullptr, name.c_str(), &used);  // read: not reported as unused
    char before[4096];
    PetscBool set = PETSC_FALSE;
    PetscOptionsGetString(nullptr, nullptr, plain.c_str(), before, sizeof before, &set);
    saved_.emplace_back(plain, set ? std::optional<std::string>(before) : std::nullopt);
    PetscOptionsSetValue(nullptr, plain.c_str(), has_value ? value.c_str() : nullptr);
  }
}

PrefixedOptions::~PrefixedOptions() {
  for (auto it = saved_.rbegin(); it != saved_.rend(); ++it) {
    if (it->second) PetscOptionsSetValue(nullptr, it->first.c_str(), it->second->empty() ? nullptr : it->second->c_str());
    else PetscOptionsClearValue(nullptr, it->first.c_str());
  }
}

}  // namespace latticedyn
