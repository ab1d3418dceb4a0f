// Case records as text lines: "case <index> ok|failed <evaluations> <newton> <wall> <slope> |
// <values> | <state> | [chain <s> <state> | ]<error> | end", numbers with 17 digits so that a
// resumed chain starts from the bit-identical state (records without the chain part, written
// before it existed, still read).
#include "drivers/batch_log.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace latticedyn {

std::uint64_t fingerprint_of(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

namespace {

const char* kHeader = "# latticedyn batch records, fingerprint ";

std::string numbers(const std::vector<double>& v) {
  std::string out;
  char buf[40];
  for (double x : v) {
    std::snprintf(buf, sizeof buf, "%s%.17g", out.empty() ? "" : " ", x);
    out += buf;
  }
  return out;
}

std::vector<double> parse_numbers(const std::string& text) {
  std::vector<double> v;
  std::istringstream is(text);
  std::string token;
  while (is >> token) v.push_back(std::strtod(token.c_str(), nullptr));
  return v;
}

bool parse_record(const std::string& full, CaseRecord* r) {
  // A record is complete only with its end mark: a line cut by an interruption never parses.
  const std::string mark = " | end";
  if (full.size() < mark.size() || full.compare(full.size() - mark.size(), mark.size(), mark) != 0) return false;
  const std::string line = full.substr(0, full.size() - mark.size());
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t bar = line.find(" | ", start);
    if (bar == std::string::npos) return false;
    parts.push_back(line.substr(start, bar - start));
    start = bar + 3;
  }
  parts.push_back(line.substr(start));
  std::istringstream head(parts[0]);
  std::string word, status;
  if (!(head >> word >> r->index >> status >> r->evaluations >> r->newton_iterations >> r->wall_seconds) || word != "case")
    return false;
  std::string slope;
  if (!(head >> slope)) return false;
  r->slope = std::strtod(slope.c_str(), nullptr);
  r->ok = status == "ok";
  r->values = parse_numbers(parts[1]);
  r->state = parse_numbers(parts[2]);
  r->error = parts[3];
  const std::string chain = "chain ";
  if (r->error.compare(0, chain.size(), chain) == 0) {
    const std::size_t bar = r->error.find(" | ");
    if (bar == std::string::npos) return false;
    std::vector<double> point = parse_numbers(r->error.substr(chain.size(), bar - chain.size()));
    if (point.empty()) return false;
    r->chain_s = point.front();
    r->chain_state.assign(point.begin() + 1, point.end());
    r->error = r->error.substr(bar + 3);
  }
  return true;
}

}  // namespace

std::map<int, CaseRecord> read_case_records(const std::filesystem::path& folder, std::uint64_t fingerprint) {
  std::map<int, CaseRecord> out;
  if (!std::filesystem::is_directory(folder)) return out;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(folder))
    if (e.path().extension() == ".log") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  const std::string expected = kHeader + std::to_string(fingerprint);
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t start = 0;
    bool first = true;
    while (true) {
      const std::size_t end = text.find('\n', start);
      if (end == std::string::npos) break;  // no newline: an interrupted write
      const std::string line = text.substr(start, end - start);
      start = end + 1;
      if (first) {
        if (line != expected)
          throw std::runtime_error(f.string() + " holds the records of another batch (other batch or model file); "
                                   "give another --output folder or delete it");
        first = false;
        continue;
      }
      CaseRecord r;
      if (parse_record(line, &r)) out[r.index] = std::move(r);
    }
  }
  return out;
}

CaseLog::CaseLog(const std::filesystem::path& file, std::uint64_t fingerprint) : path_(file) {
  const bool fresh = !std::filesystem::exists(file) || std::filesystem::file_size(file) == 0;
  bool cut = false;  // an interrupted write left a line without its newline
  if (!fresh) {
    std::ifstream in(file, std::ios::binary | std::ios::ate);
    in.seekg(-1, std::ios::end);
    cut = in.get() != '\n';
  }
  file_ = std::fopen(file.c_str(), "a");
  if (!file_) throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(errno));
  if (fresh) std::fprintf(file_, "%s%llu\n", kHeader, static_cast<unsigned long long>(fingerprint));
  if (cut) std::fputc('\n', file_);
  std::fflush(file_);
}

CaseLog::~CaseLog() {
  if (file_) std::fclose(file_);
}

void CaseLog::append(const CaseRecord& r) {
  std::string error = r.error;
  for (char& c : error)
    if (c == '\n' || c == '\r') c = ' ';
  std::string chain;
  if (!r.chain_state.empty()) {
    std::vector<double> point{r.chain_s};
    point.insert(point.end(), r.chain_state.begin(), r.chain_state.end());
    chain = "chain " + numbers(point) + " | ";
  }
  std::fprintf(file_, "case %d %s %d %d %.6g %.17g | %s | %s | %s%s | end\n", r.index, r.ok ? "ok" : "failed",
               r.evaluations, r.newton_iterations, r.wall_seconds, r.slope, numbers(r.values).c_str(),
               numbers(r.state).c_str(), chain.c_str(), error.c_str());
  if (std::fflush(file_) != 0) throw std::runtime_error("cannot write " + path_.string() + ": " + std::strerror(errno));
}

}  // namespace latticedyn
