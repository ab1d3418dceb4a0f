// Small queries on the model data.
#include "assembly/model.hpp"

namespace latticedyn {

const char* to_string(ConstraintType t) {
  switch (t) {
    case ConstraintType::fixed: return "fixed";
    case ConstraintType::revolute: return "revolute";
    case ConstraintType::prismatic: return "prismatic";
    case ConstraintType::spherical: return "spherical";
  }
  return "?";
}

int Constraint::rows() const {
  const int driven = drive >= 0 ? 1 : 0;
  switch (type) {
    case ConstraintType::fixed: return 6;
    case ConstraintType::revolute: return 5 + driven;
    case ConstraintType::prismatic: return 5 + driven;
    case ConstraintType::spherical: return 3;
  }
  return 0;
}

int Model::num_free_dofs() const {
  int n = 0;
  for (const auto& b : blocks)
    if (!b.fixed) n += b.size();
  return n;
}

int Model::num_multipliers() const {
  int n = 0;
  for (const auto& c : constraints) n += c.rows();
  return n;
}

}  // namespace latticedyn
