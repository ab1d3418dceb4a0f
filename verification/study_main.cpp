// latticedyn_study STUDY.yaml [--out DIR] [--quick]: runs a verification study of thesis
// chapter 8 (its kind named in the file), writes CSV and markdown tables to DIR and exits 0 when
// every acceptance check passes, 1 when one fails, 2 for bad input.
#include "verification/study.hpp"

#include <slepcsys.h>

#include <cstdio>
#include <cstring>

namespace latticedyn {
namespace {

int run_study(const std::string& path, const std::string& out, bool quick) {
  const Study study(path, out, quick);
  const std::string kind =
      study.root()["study"].as_choice({"end_moment", "self_weight", "fixed_axis_rotation", "lattice_reduction"});
  std::printf("study %s: %s\nsource: %s\n", path.c_str(), study.root()["title"].as_string().c_str(),
              study.root()["source"].as_string().c_str());
  const std::vector<Verdict> verdicts = kind == "end_moment"            ? run_end_moment_study(study)
                                        : kind == "self_weight"         ? run_self_weight_study(study)
                                        : kind == "fixed_axis_rotation" ? run_fixed_axis_rotation_study(study)
                                                                        : run_lattice_reduction_study(study);
  bool all = !verdicts.empty();
  for (const Verdict& v : verdicts) {
    std::printf("%s  %s\n", v.pass ? "pass" : "FAIL", v.what.c_str());
    all = all && v.pass;
  }
  std::printf("%s (tables in %s)\n", all ? "all checks pass" : "SOME CHECKS FAILED", out.c_str());
  return all ? 0 : 1;
}

}  // namespace
}  // namespace latticedyn

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: latticedyn_study STUDY.yaml [--out DIR] [--quick] [PETSc options]\n");
    return 2;
  }
  const std::string path = argv[1];
  std::string out = "results/study";
  bool quick = false;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
    if (!std::strcmp(argv[i], "--quick")) quick = true;
  }
  if (SlepcInitialize(&argc, &argv, nullptr, nullptr) != 0) return 3;
  int code = 0;
  try {
    code = latticedyn::run_study(path, out, quick);
  } catch (const latticedyn::InputError& e) {
    std::fprintf(stderr, "latticedyn_study: error: %s\n", e.what());
    code = 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "latticedyn_study: error: %s\n", e.what());
    code = 1;
  }
  SlepcFinalize();
  return code;
}
