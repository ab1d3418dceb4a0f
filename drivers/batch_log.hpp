// The records a batch leaves behind, one line per finished case in one file per group, written
// as each case ends, so that an interrupted batch loses at most the cases under way.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace latticedyn {

struct CaseRecord {
  int index = -1;
  bool ok = false;
  int evaluations = 0;       ///< solves (static solves, or one run)
  int newton_iterations = 0;
  double wall_seconds = 0.0;
  double slope = 0.0;        ///< target cases: d(adjusted value) / d(measure) at the solution
  std::vector<double> values;  ///< the result columns (BatchRunner::result_columns)
  std::vector<double> state;   ///< equilibrium coordinates and multipliers (static cases)
  /// Target cases: the earlier point of the chain's history after the case (a secant probe or
  /// an earlier equilibrium; empty when there is none). With (adjusted value, state) it is what
  /// the chain's next case extrapolates its start from, so a resume rebuilds it exactly.
  double chain_s = 0.0;
  std::vector<double> chain_state;
  std::string error;
};

/// Every record under `folder` from files whose first line carries `fingerprint`; a file with
/// another fingerprint is an error (the folder holds another batch). Incomplete last lines (an
/// interrupted write) are ignored. Later records of the same case replace earlier ones.
std::map<int, CaseRecord> read_case_records(const std::filesystem::path& folder, std::uint64_t fingerprint);

/// Appends records to one group's file, flushed after each.
class CaseLog {
 public:
  CaseLog(const std::filesystem::path& file, std::uint64_t fingerprint);
  ~CaseLog();
  CaseLog(const CaseLog&) = delete;
  CaseLog& operator=(const CaseLog&) = delete;
  void append(const CaseRecord& r);

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

/// FNV-1a of the text: a fingerprint that stays the same across runs and machines.
std::uint64_t fingerprint_of(const std::string& text);

}  // namespace latticedyn
