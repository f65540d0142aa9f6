// texbake batch JOBS.jsonl [--results R.jsonl] [--fail-fast] [--shard K/N]
//   [--skip-existing] [--threads N] [-q]        (SPEC section 12, issue #15)
//
// One `texbake bake` job a line: a JSON object with the command line's keys
// by their long names ("mesh", "texture", "proxy" | "proxy_file" | "cameras"
// (+ "images") | "layers", "output",
// "center": [0, 0, 0], "samples": 4, "linear": true, ...). Each line is read
// by parse_batch_line (bake/cli/batch_job.h: bounded, strict JSON; every key
// an option of `texbake bake`) into the argv of the single command, run by a
// fresh CLI11 app of make_cli_app in this process, so options are parsed,
// validated and reported by exactly the code of `texbake bake`, with the
// same messages. Relative paths are relative to the current folder, as for
// the single command.
//
// Jobs run in line order; a failing job is reported with its line number
// and the single command's message ("texbake: error: JOBS:LINE: message")
// and the others still run (--fail-fast stops at the first failure). Line i
// (1-based) is job index i - 1; --shard K/N runs the jobs whose index modulo
// N is K (Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT).
// Blank lines are no job. --skip-existing skips a job whose outputs all
// exist and none is older than any of its inputs (make's rule). Exit 0 only
// if every job of the shard succeeded or was skipped; 1 otherwise; 2 for the
// batch's own usage errors. --results is truncated at the start and gets
// each job's line as soon as the job ends (appended, flushed).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "bake/cli/app.h"
#include "bake/cli/atlas_target.h"
#include "bake/cli/batch_job.h"
#include "bake/cli/commands.h"
#include "bake/util/timing.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/regular_file.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

struct BatchOptions {
  std::string jobs;
  std::string results;
  bool fail_fast = false;
  std::string shard;  // "K/N"
  bool skip_existing = false;
  int threads = 0;  // for jobs without "threads"
  bool quiet = false;
};

struct Shard {
  long k = 0, n = 1;
};

// "K/N" with 0 <= K < N. kInvalidArgument naming --shard otherwise.
Expected<Shard> parse_shard(const std::string& text) {
  Shard s;
  char slash = 0, extra = 0;
  if (text.empty()) return s;
  if (std::sscanf(text.c_str(), "%ld%c%ld%c", &s.k, &slash, &s.n, &extra) != 3 || slash != '/' ||
      s.n < 1 || s.k < 0 || s.k >= s.n) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--shard '" + text + "' is not K/N with 0 <= K < N (e.g. 0/4)");
  }
  return s;
}

std::string string_key(const ordered_json& job, const char* key) {
  auto it = job.find(key);
  return it != job.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// The files the job names, by the keys of `texbake bake`'s flags: -o is an
// atlas (with an OBJ's MTL and image) by resolve_target.
JobFileNames job_file_names(const ordered_json& job) {
  JobFileNames f;
  f.mesh = string_key(job, "mesh");
  f.texture = string_key(job, "texture");
  f.proxy_file = string_key(job, "proxy_file");
  f.cameras = string_key(job, "cameras");
  f.images = string_key(job, "images");
  f.layers = string_key(job, "layers");
  f.output = string_key(job, "output");
  AtlasFlags flags;
  flags.target = string_key(job, "target");
  Expected<BakeTarget> target = resolve_target(flags, f.output);
  f.atlas = !f.output.empty() && target && *target == BakeTarget::kAtlas;
  const std::string format = string_key(job, "format");
  f.write.format = format == "exr"     ? AtlasFormat::kExr
                   : format == "png16" ? AtlasFormat::kPng16
                                       : AtlasFormat::kPng8;
  f.report = string_key(job, "report");
  return f;
}

// The files the job reads and writes, as `texbake bake` lists them
// (job_inputs, job_outputs: the layers file and what it names, the camera
// model and its photos, an atlas's MTL and image, --report).
struct JobFiles {
  std::vector<fs::path> inputs, outputs;
};

JobFiles job_files(const JobFileNames& names) {
  JobFiles f;
  for (const NamedFile& in : job_inputs(names)) f.inputs.push_back(in.path);
  for (const NamedFile& out : job_outputs(names)) f.outputs.push_back(out.path);
  return f;
}

// Every output exists and none is older than any input (make's rule); false
// when an input is missing (the job runs and reports it).
bool up_to_date(const JobFiles& f) {
  if (f.outputs.empty()) return false;
  std::error_code ec;
  fs::file_time_type newest_input = fs::file_time_type::min();
  for (const fs::path& p : f.inputs) {
    const fs::file_time_type t = fs::last_write_time(p, ec);
    if (ec) return false;
    newest_input = std::max(newest_input, t);
  }
  for (const fs::path& p : f.outputs) {
    const fs::file_time_type t = fs::last_write_time(p, ec);
    if (ec || t < newest_input) return false;
  }
  return true;
}

// The outcome of one job, as its line of --results.
struct JobResult {
  std::size_t line = 0;
  std::string status;  // "ok", "failed", "skipped"
  int exit_code = 0;
  std::string error;                  // the single command's message ("" if none)
  std::vector<std::string> warnings;  // its "texbake: warning: " lines
  std::vector<fs::path> outputs;
  std::optional<ordered_json> report;  // the bake's report (ok jobs)
  double seconds = 0;
};

ordered_json result_json(const JobResult& r) {
  ordered_json j;
  j["line"] = r.line;
  j["status"] = r.status;
  j["exit"] = r.exit_code;
  j["error"] = r.error.empty() ? ordered_json() : ordered_json(r.error);
  j["warnings"] = r.warnings;
  ordered_json outs = ordered_json::array();
  for (const fs::path& p : r.outputs) outs.push_back(p.string());
  j["outputs"] = outs;
  if (r.report) {
    j["target"] = (*r.report)["target"];
    j["counts"] = (*r.report)["counts"];
    j["timings"] = (*r.report)["timings"];
  } else {
    j["counts"] = ordered_json();
    j["timings"] = ordered_json();
  }
  j["seconds"] = r.seconds;
  return j;
}

// Runs argv through a fresh app, stderr captured: error and warning lines.
void run_job(const std::vector<std::string>& argv, JobResult& r) {
  std::optional<std::string> report;
  CliHooks hooks;
  hooks.on_report = [&](const std::string& json) { report = json; };
  std::unique_ptr<CliApp> cli = make_cli_app(hooks);
  std::vector<const char*> args;
  for (const std::string& a : argv) args.push_back(a.c_str());
  std::ostringstream err;
  std::streambuf* saved = std::cerr.rdbuf(err.rdbuf());
  std::optional<int> code = parse_cli(*cli, static_cast<int>(args.size()), args.data());
  if (!code) code = run_parsed(*cli);
  std::cerr.rdbuf(saved);
  r.exit_code = *code;
  std::istringstream lines(err.str());
  for (std::string line; std::getline(lines, line);) {
    static const std::string kError = "texbake: error: ", kWarning = "texbake: warning: ";
    if (line.rfind(kError, 0) == 0 && r.error.empty()) r.error = line.substr(kError.size());
    if (line.rfind(kWarning, 0) == 0) r.warnings.push_back(line.substr(kWarning.size()));
  }
  if (r.exit_code == 0 && report) r.report = ordered_json::parse(*report);
  r.status = r.exit_code == 0 ? "ok" : "failed";
  if (r.exit_code != 0 && r.error.empty())
    r.error = "the job failed (exit " + std::to_string(r.exit_code) + ")";
}

// --results: truncated at the start, then each job's line appended and
// flushed as the job ends, so a batch that is killed keeps the record of the
// jobs it finished.
class ResultsFile {
 public:
  Status open(const std::string& path) {
    path_ = path;
    if (path.empty()) return ok_status();
    if (Status s = check_writable(path); !s) return s;
    out_.open(path, std::ios::binary | std::ios::trunc);
    if (!out_) return make_error(ErrorCode::kIo, "cannot write results " + path);
    return ok_status();
  }
  // Paths and messages may hold bytes that are not UTF-8 (a photo's name):
  // those become U+FFFD rather than end the batch.
  Status append(const ordered_json& line) {
    if (path_.empty()) return ok_status();
    out_ << line.dump(-1, ' ', false, ordered_json::error_handler_t::replace) << '\n';
    out_.flush();
    if (!out_) return make_error(ErrorCode::kIo, "cannot write results " + path_);
    return ok_status();
  }

 private:
  std::string path_;
  std::ofstream out_;
};

int run_batch(const BatchOptions& o) {
  const auto start = Clock::now();
  Expected<Shard> shard = parse_shard(o.shard);
  if (!shard) return report_error(shard.error());
  // The jobs file is an input, --results an output, of every job.
  if (Status s = check_distinct_files({{"JOBS", o.jobs}}, {{"--results", o.results}}); !s) {
    return report_error(s.error());
  }
  if (Status s = check_regular_file(o.jobs, "a jobs file"); !s) return report_error(s.error());
  std::ifstream in(o.jobs, std::ios::binary);
  if (!in) return report_error(ErrorCode::kIo, o.jobs + ": cannot be read");
  // The shard's lines (1-based numbers), read first to count them.
  std::vector<std::pair<std::size_t, std::string>> lines;
  std::string text;
  for (std::size_t number = 1; std::getline(in, text); ++number) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    if ((number - 1) % shard->n == static_cast<std::size_t>(shard->k))
      lines.emplace_back(number, text);
  }
  if (in.bad()) return report_error(ErrorCode::kIo, o.jobs + ": read error");

  ResultsFile results;
  if (Status s = results.open(o.results); !s) return report_error(s.error());
  std::size_t ok = 0, failed = 0, skipped = 0, done = 0;
  for (const auto& [number, line] : lines) {
    const auto job_start = Clock::now();
    JobResult r;
    r.line = number;
    Expected<BatchJob> job = parse_batch_line(line, o.threads);
    JobFileNames names;
    if (job) {
      names = job_file_names(job->keys);
      for (const NamedFile& out : job_outputs(names)) r.outputs.push_back(out.path);
      // No output may be an input: the jobs file is an input, --results an
      // output, of every job.
      JobFileNames in_batch = names;
      in_batch.manifest = o.jobs;
      in_batch.results = o.results;
      if (Status s = check_job_files(in_batch); !s) job = s.error();
    }
    if (!job) {
      r.status = "failed";
      r.exit_code = exit_code(job.error());
      r.error = job.error().message;
    } else if (o.skip_existing && up_to_date(job_files(names))) {
      r.status = "skipped";
    } else {
      run_job(job->argv, r);
    }
    r.seconds = seconds_since(job_start);
    ++done;
    const std::string where = o.jobs + ":" + std::to_string(number);
    if (r.status == "failed") {
      ++failed;
      std::cerr << "texbake: error: " << where << ": " << r.error << "\n";
    } else {
      ++(r.status == "ok" ? ok : skipped);
    }
    if (!o.quiet) {
      std::fprintf(stderr, "texbake: batch [%zu/%zu] %s %s (%.2f s)%s%s\n", done, lines.size(),
                   where.c_str(), r.status.c_str(), r.seconds,
                   r.outputs.empty() || r.status == "failed" ? "" : " -> ",
                   r.outputs.empty() || r.status == "failed" ? "" : r.outputs[0].c_str());
    }
    if (Status s = results.append(result_json(r)); !s) return report_error(s.error());
    if (o.fail_fast && r.status == "failed") break;
  }
  if (!o.quiet) {
    std::printf("batch: %zu ok, %zu failed, %zu skipped, %zu not run of %zu jobs in %.2f s\n", ok,
                failed, skipped, lines.size() - done, lines.size(), seconds_since(start));
    std::fflush(stdout);
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace

RunFunction add_batch_command(CLI::App& app) {
  auto o = std::make_shared<BatchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "batch",
      "Run many bakes: one JSON object a line, with the keys of `texbake bake` by their long "
      "names (\"mesh\", \"texture\", \"proxy\", \"output\", \"samples\", ...). A failing job is "
      "reported with its line and the others still run; exit 0 only if all succeeded.");
  cmd->add_option("jobs", o->jobs, "the jobs file (JSON lines)")->required();
  cmd->add_option("--results", o->results,
                  "write one JSON line per job run (line, status, error, outputs, counts, "
                  "timings) to this file, emptied at the start; each line is written as "
                  "soon as its job ends");
  cmd->add_flag("--fail-fast", o->fail_fast, "stop at the first failing job");
  cmd->add_option("--shard", o->shard,
                  "K/N: run only the jobs whose index (line number - 1) modulo N is K")
      ->type_name("K/N");
  cmd->add_flag("--skip-existing", o->skip_existing,
                "skip jobs whose outputs exist and are not older than their inputs");
  cmd->add_option("--threads", o->threads,
                  "worker threads of each job that does not set \"threads\" (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_flag("-q,--quiet", o->quiet, "no line per job, no summary (errors still print)");
  return [o] { return run_batch(*o); };
}

}  // namespace texbake::cli
