// States of a model for the results writer's tests: its initial state moved away by different
// amounts at each step, gathered on one rank.
#pragma once

#include "assembly/system_assembler.hpp"

#include <gtest/gtest.h>

#include <petscvec.h>

#include <cmath>
#include <memory>
#include <vector>

namespace latticedyn::testing {

/// A model, its assembler and `n` gathered states at t = 0.1 k whose coordinates, rates and
/// multipliers move away from the initial state by different amounts at each step.
struct Recording {
  Model model;
  std::unique_ptr<SystemAssembler> sa;
  std::vector<ModelState> states;

  Recording(Model m, int n) : model(std::move(m)), sa(std::make_unique<SystemAssembler>(model, PETSC_COMM_SELF)) {
    Vec U, V;
    EXPECT_EQ(sa->create_vector(&U), 0);
    EXPECT_EQ(sa->create_vector(&V), 0);
    EXPECT_EQ(sa->initial_state(U, V), 0);
    const int size = sa->dofs().global_size();
    std::vector<double> u0(size), v0(size);
    PetscScalar *u, *v;
    VecGetArray(U, &u);
    VecGetArray(V, &v);
    std::copy(u, u + size, u0.begin());
    std::copy(v, v + size, v0.begin());
    VecRestoreArray(U, &u);
    VecRestoreArray(V, &v);
    states.reserve(n);
    for (int k = 0; k < n; ++k) {
      VecGetArray(U, &u);
      VecGetArray(V, &v);
      for (int i = 0; i < size; ++i) {
        u[i] = u0[i] + 0.05 * k * std::sin(1.3 * i + 0.7) + (i >= size - model.num_multipliers() ? 10.0 * k + i : 0.0);
        v[i] = v0[i] + 0.1 * k * std::cos(0.9 * i);
      }
      VecRestoreArray(U, &u);
      VecRestoreArray(V, &v);
      states.emplace_back(model, sa->dofs());
      EXPECT_EQ(sa->gather(0.1 * k, U, V, nullptr, Parametrization::rotation_vector_rates, &states.back()), 0);
    }
    VecDestroy(&U);
    VecDestroy(&V);
  }
};

}  // namespace latticedyn::testing
