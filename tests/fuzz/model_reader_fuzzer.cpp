// libFuzzer target of the model reader (issue 13): every input is the text of a model file, read
// by read_simulation_from_string. Bad input must end in InputError located in the model, the
// reader's one documented answer (io/model_reader.hpp); anything else is a finding: another
// exception (uncaught here, so the process aborts), a crash, an ASan or UBSan report, a leak, a
// timeout or running out of memory. Built with -DLATTICEDYN_FUZZ=ON, run by scripts/fuzz.sh
// (corpus: tests/fuzz/corpus/model_reader).
//
// The reader writes nothing. It reads other files only for `start_state` (HDF5, read-only;
// `base:` is followed by read_simulation alone, from a string it is an unknown key); a relative
// path is taken against the working directory, which scripts/fuzz.sh makes an empty temporary
// one. No PETSc or MPI: reading a model needs neither.
#include "io/model_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {
const std::string kName = "fuzz.yaml";
const bool kPrint = std::getenv("LATTICEDYN_FUZZ_PRINT") != nullptr;  // triage: what the reader said
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // A super truss's member loop may run threads; one keeps runs reproducible and the machine free.
  setenv("OMP_NUM_THREADS", "1", 0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    latticedyn::read_simulation_from_string(text, kName);
    if (kPrint) std::fprintf(stderr, "read: a model\n");
  } catch (const latticedyn::InputError& e) {
    // Bad input, as documented: "file:line:col: key: what was expected", naming the model.
    if (kPrint) std::fprintf(stderr, "InputError: %s\n", e.what());
    if (e.file() != kName) {
      std::fprintf(stderr, "model_reader_fuzzer: an InputError that does not name the model: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
