// PETSc options in model files: split as PETSc splits them (names, values, negative numbers,
// quotes), solver settings and terminal monitors allowed, everything that reaches files or other
// processes refused.
#include "io/petsc_option_policy.hpp"

#include <gtest/gtest.h>

namespace latticedyn {
namespace {

TEST(PetscOptionPolicy, SplitsNamesValuesNumbersAndQuotes) {
  const auto o = split_petsc_options("-snes_atol 1e-6 -snes_rtol -1e-50  --ts_max_steps\t3 -snes_monitor "
                                     "-ts_monitor \"ascii::ascii_info_detail\" -x '-1'");
  ASSERT_EQ(o.size(), 6u);
  EXPECT_EQ(o[0].name, "snes_atol");
  EXPECT_EQ(o[0].value, "1e-6");
  EXPECT_EQ(o[1].value, "-1e-50");  // a number, not a name
  EXPECT_EQ(o[2].name, "ts_max_steps");
  EXPECT_EQ(o[2].value, "3");
  EXPECT_EQ(o[3].name, "snes_monitor");
  EXPECT_EQ(o[3].value, "");  // the next token is a name
  EXPECT_EQ(o[4].value, "ascii::ascii_info_detail");
  EXPECT_EQ(o[5].value, "-1");
}

TEST(PetscOptionPolicy, AllowsSolverSettingsAndTerminalMonitors) {
  for (const char* options : {"-snes_atol 1e-6 -snes_rtol 1e-50", "-ts_type alpha2 -ksp_type gmres -pc_type asm",
                              "-snes_monitor", "-snes_monitor stdout", "-ts_monitor ascii::ascii_info_detail",
                              "-ksp_view", "-mat_mumps_icntl_14 100", "-options_left", "-pc_asm_overlap 2"})
    for (const PetscOptionToken& o : split_petsc_options(options))
      EXPECT_FALSE(refused_model_option(o)) << options << ": " << refused_model_option(o).value_or("");
}

TEST(PetscOptionPolicy, RefusesFilesViewersWindowsAndProcesses) {
  for (const char* options :
       {"-options_file opts.txt", "-options_file_yaml o.yaml", "-log_view :log.txt", "-log_view ascii:log.txt",
        "-ksp_view_mat binary:J.bin", "-snes_monitor :out.txt", "-ts_monitor_solution draw", "-mat_view hdf5:m.h5",
        "-vec_view vtk:v.vts", "-snes_monitor_lg_residualnorm", "-ts_save_trajectory", "-ts_trajectory_dirname d",
        "-log_trace t.txt", "-history h.txt", "-on_error_attach_debugger", "-start_in_debugger", "-info",
        "-malloc_dump", "-display :0", "-viewer_binary_filename f", "-ksp_view socket", "-snes_view saws",
        "-log_view", "-fp_trap", "-pc_type /tmp/x", "--options_file opts.txt"}) {
    bool refused = false;
    for (const PetscOptionToken& o : split_petsc_options(options)) refused = refused || refused_model_option(o);
    EXPECT_TRUE(refused) << options;
  }
}

}  // namespace
}  // namespace latticedyn
