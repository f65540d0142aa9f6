// texbake batch JOBS.jsonl [--results R.jsonl] [--fail-fast] [--shard K/N]
//   [--skip-existing] [--threads N] [-q]        (SPEC section 12, issue #15)
//
// One `texbake bake` job a line: a JSON object with the job options' keys
// (texbake/job_options.h: the command line's long names, "proxy_file" for
// --proxy-file; "mesh", "texture", "proxy" | "proxy_file" | "cameras" (+
// "images") | "layers", "output", "center": [0, 0, 0], "samples": 4,
// "linear": true, ...). The library runs them (texbake::run_batch: each
// line read by job_settings_from_json, made a Job by job_from_settings with
// the same checks and messages as `texbake bake`, run by run_job); this
// file reads the jobs file, picks the shard's lines and prints. Relative
// paths are relative to the current folder, as for the single command.
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
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bake/cli/commands.h"
#include "mesh_io/regular_file.h"
#include "texbake/job_options.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;

struct BatchCliOptions {
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

int run_batch(const BatchCliOptions& o) {
  Expected<Shard> shard = parse_shard(o.shard);
  if (!shard) return report_error(shard.error());
  if (Status s = check_distinct_files({{"JOBS", o.jobs}}, {{"--results", o.results}}); !s) {
    return report_error(s.error());
  }
  if (Status s = check_regular_file(o.jobs, "a jobs file"); !s) return report_error(s.error());
  std::ifstream in(o.jobs, std::ios::binary);
  if (!in) return report_error(ErrorCode::kIo, o.jobs + ": cannot be read");
  // The shard's lines (1-based numbers), read first to count them.
  std::vector<BatchJob> jobs;
  std::string text;
  for (std::size_t number = 1; std::getline(in, text); ++number) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    if ((number - 1) % shard->n == static_cast<std::size_t>(shard->k))
      jobs.push_back({number, text});
  }
  if (in.bad()) return report_error(ErrorCode::kIo, o.jobs + ": read error");

  BatchOptions options;
  options.manifest = o.jobs;
  options.results = o.results;
  options.fail_fast = o.fail_fast;
  options.skip_existing = o.skip_existing;
  options.threads = o.threads;
  std::size_t done = 0;
  options.on_job_end = [&](const BatchJobResult& r) {
    ++done;
    const std::string where = o.jobs + ":" + std::to_string(r.line);
    if (r.status == "failed") {
      std::cerr << "texbake: error: " << where << ": " << r.result.error->message << "\n";
    }
    if (!o.quiet) {
      const bool show_output = !r.outputs.empty() && r.status != "failed";
      std::fprintf(stderr, "texbake: batch [%zu/%zu] %s %s (%.2f s)%s%s\n", done, jobs.size(),
                   where.c_str(), r.status.c_str(), r.result.seconds, show_output ? " -> " : "",
                   show_output ? r.outputs[0].c_str() : "");
    }
  };
  const BatchResult batch = texbake::run_batch(jobs, options);
  if (batch.error) return report_error(*batch.error);
  if (!o.quiet) {
    std::printf("batch: %zu ok, %zu failed, %zu skipped, %zu not run of %zu jobs in %.2f s\n",
                batch.ok, batch.failed, batch.skipped, batch.not_run, jobs.size(), batch.seconds);
    std::fflush(stdout);
  }
  return batch.failed == 0 ? 0 : 1;
}

}  // namespace

RunFunction add_batch_command(CLI::App& app) {
  auto o = std::make_shared<BatchCliOptions>();
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
