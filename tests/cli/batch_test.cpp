// texbake batch (SPEC section 12, issue #15): every job's output and error
// are the single command's (the same argv run as `texbake bake`), failing
// jobs are reported with their line and the others still run, exit codes,
// --results (each line as its job ends), --fail-fast, --shard and
// --skip-existing; a bad line (not JSON, nested too deep, a number out of
// range, an unknown key, a value that looks like a flag) is that line's error.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "run_texbake.h"

namespace {

namespace fs = std::filesystem;
using texbake::testing_cli::fresh_test_dir;
using texbake::testing_cli::run_texbake;
using texbake::testing_cli::RunResult;
using texbake::testing_cli::shell_quote;
using texbake::testing_cli::slurp;

const std::string kData = TEXBAKE_DATA_DIR;

// The "texbake: error: " lines of a run's stderr, without that prefix.
std::vector<std::string> error_lines(const std::string& err) {
  std::vector<std::string> out;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("texbake: error: ", 0) == 0) out.push_back(line.substr(16));
  }
  return out;
}

std::vector<nlohmann::json> read_results(const fs::path& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
  return out;
}

class BatchCli : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override { dir = fresh_test_dir("batch"); }
  void TearDown() override { fs::remove_all(dir); }

  fs::path write_jobs(const std::vector<std::string>& lines) {
    const fs::path jobs = dir / "jobs.jsonl";
    std::ofstream out(jobs);
    for (const std::string& l : lines) out << l << "\n";
    return jobs;
  }
  std::string out(const std::string& name) const { return (dir / name).string(); }
  RunResult batch(const std::string& args) {
    return run_texbake("batch " + shell_quote((dir / "jobs.jsonl").string()) + " " + args);
  }
};

// A small mushroom bake with every key form: a string, numbers, a vector,
// a value starting with '-', a boolean flag.
std::string mushroom_job(const std::string& output) {
  return R"({"mesh":")" + kData + R"(/mushroom.off","texture":")" + kData +
         R"(/earth.jpg","proxy":"sphere","center":[0,0,0.5],"up":"-y","samples":2,"linear":true,"ascii":false,"output":")" +
         output + R"("})";
}
const std::string kMushroomArgs = "bake " + shell_quote(kData + "/mushroom.off") + " --texture " +
                                  shell_quote(kData + "/earth.jpg") +
                                  " --proxy sphere --center 0,0,0.5 --up -y --samples 2 --linear";

TEST_F(BatchCli, JobsEqualTheSingleCommandAndFailuresAreReportedByLine) {
  const std::string missing_mesh = out("missing.off");
  const std::string missing_image = out("missing.png");
  write_jobs({
      mushroom_job(out("a.ply")),
      R"({"mesh":")" + missing_mesh + R"(","texture":")" + kData +
          R"(/earth.jpg","proxy":"sphere","output":")" + out("b.ply") + R"("})",
      "",
      R"({"mesh":")" + kData + R"(/mushroom.off","texture":")" + missing_image +
          R"(","proxy":"sphere","output":")" + out("c.ply") + R"("})",
      R"({"mesh":")" + kData + R"(/mushroom.off","texture":")" + kData +
          R"(/earth.jpg","proxy":"sphere","samples":0,"output":")" + out("d.ply") + R"("})",
      R"({"mesh":")" + kData + R"(/mushroom.off","texture":")" + kData +
          R"(/earth.jpg","proxy":"sphere","uv":"proxy","size":64,"output":")" + out("e.obj") +
          R"("})",
  });
  const RunResult r = batch("--results " + shell_quote(out("results.jsonl")));
  EXPECT_EQ(r.exit_code, 1) << r.err;

  // The good jobs' outputs are the single command's, byte for byte.
  const RunResult single = run_texbake(kMushroomArgs + " -q -o " + shell_quote(out("a1.ply")));
  ASSERT_EQ(single.exit_code, 0) << single.err;
  EXPECT_EQ(slurp(out("a.ply")), slurp(out("a1.ply")));
  ASSERT_EQ(run_texbake("bake " + shell_quote(kData + "/mushroom.off") + " --texture " +
                        shell_quote(kData + "/earth.jpg") +
                        " --proxy sphere --uv proxy --size 64 -q -o " + shell_quote(out("e1.obj")))
                .exit_code,
            0);
  EXPECT_EQ(slurp(out("e.png")), slurp(out("e1.png")));

  // Each failure: "JOBS:LINE: " and the single command's message.
  const auto single_error = [&](const std::string& args) {
    const std::vector<std::string> e = error_lines(run_texbake(args).err);
    return e.empty() ? std::string("(none)") : e[0];
  };
  const std::string jobs = (dir / "jobs.jsonl").string();
  const std::vector<std::string> errors = error_lines(r.err);
  ASSERT_EQ(errors.size(), 3u) << r.err;
  EXPECT_EQ(errors[0], jobs + ":2: " + missing_mesh + ": no such file");
  EXPECT_EQ(errors[0], jobs + ":2: " +
                           single_error("bake " + shell_quote(missing_mesh) + " --texture " +
                                        shell_quote(kData + "/earth.jpg") + " --proxy sphere -o " +
                                        shell_quote(out("b.ply"))));
  EXPECT_EQ(errors[1], jobs + ":4: " +
                           single_error("bake " + shell_quote(kData + "/mushroom.off") +
                                        " --texture " + shell_quote(missing_image) +
                                        " --proxy sphere -o " + shell_quote(out("c.ply"))));
  EXPECT_NE(errors[1].find(missing_image), std::string::npos);
  EXPECT_EQ(errors[2],
            jobs + ":5: " +
                single_error("bake " + shell_quote(kData + "/mushroom.off") + " --texture " +
                             shell_quote(kData + "/earth.jpg") + " --proxy sphere --samples 0 -o " +
                             shell_quote(out("d.ply"))));
  EXPECT_FALSE(fs::exists(out("b.ply")) || fs::exists(out("c.ply")) || fs::exists(out("d.ply")));

  // One result line per job (the blank line 3 is none), in order.
  const std::vector<nlohmann::json> results = read_results(out("results.jsonl"));
  ASSERT_EQ(results.size(), 5u);
  const int lines[] = {1, 2, 4, 5, 6};
  const char* status[] = {"ok", "failed", "failed", "failed", "ok"};
  const int exits[] = {0, 1, 1, 2, 0};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(results[i]["line"], lines[i]);
    EXPECT_EQ(results[i]["status"], status[i]);
    EXPECT_EQ(results[i]["exit"], exits[i]);
  }
  EXPECT_EQ(results[1]["error"], missing_mesh + ": no such file");
  // Counts and timings of the good jobs are their bake's report: the
  // mushroom has 2337 vertices (data/mushroom.off's header).
  EXPECT_EQ(results[0]["counts"]["vertices"], 2337);
  EXPECT_EQ(results[0]["target"], "vertex");
  EXPECT_GT(results[0]["timings"]["total"].get<double>(), 0);
  EXPECT_EQ(results[4]["target"], "atlas");
  EXPECT_EQ(results[4]["outputs"],
            nlohmann::json::array({out("e.obj"), out("e.mtl"), out("e.png")}));
  EXPECT_TRUE(results[1]["counts"].is_null());
}

TEST_F(BatchCli, ExitZeroOnlyWhenAllSucceed) {
  write_jobs({mushroom_job(out("a.ply")), mushroom_job(out("b.ply"))});
  const RunResult r = batch("");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, r.out.substr(0, r.out.find('\n') + 1));  // the summary line only
  EXPECT_EQ(r.out.rfind("batch: 2 ok, 0 failed, 0 skipped, 0 not run of 2 jobs in ", 0), 0u)
      << r.out;
  EXPECT_NE(r.err.find("texbake: batch [1/2] "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("texbake: batch [2/2] "), std::string::npos) << r.err;
}

TEST_F(BatchCli, FailFastStopsAtTheFirstFailure) {
  write_jobs({mushroom_job(out("a.ply")), "[1, 2]", mushroom_job(out("c.ply"))});
  const RunResult r = batch("--fail-fast --results " + shell_quote(out("r.jsonl")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(error_lines(r.err), std::vector<std::string>{(dir / "jobs.jsonl").string() +
                                                         ":2: expected a JSON object, not array"});
  EXPECT_TRUE(fs::exists(out("a.ply")));
  EXPECT_FALSE(fs::exists(out("c.ply")));
  EXPECT_EQ(read_results(out("r.jsonl")).size(), 2u);
}

TEST_F(BatchCli, ShardsSplitTheLinesByIndexModuloN) {
  std::vector<std::string> lines;
  for (int i = 0; i < 5; ++i) lines.push_back(mushroom_job(out("m" + std::to_string(i) + ".ply")));
  write_jobs(lines);
  const RunResult r = batch("--shard 1/3 --threads 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // Lines 2 and 5 (indices 1 and 4).
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(fs::exists(out("m" + std::to_string(i) + ".ply")), i % 3 == 1);
  for (const char* bad : {"3/3", "-1/2", "1", "0/0", "a/b", "1/2x"}) {
    const RunResult b = batch(std::string("--shard ") + shell_quote(bad));
    EXPECT_EQ(b.exit_code, 2) << bad;
    EXPECT_EQ(error_lines(b.err),
              std::vector<std::string>{std::string("--shard '") + bad +
                                       "' is not K/N with 0 <= K < N (e.g. 0/4)"});
  }
}

TEST_F(BatchCli, SkipExistingSkipsUpToDateOutputsOnly) {
  write_jobs({mushroom_job(out("a.ply")), mushroom_job(out("b.ply"))});
  ASSERT_EQ(batch("-q").exit_code, 0);
  // b's output made older than its inputs: b runs again, a is skipped.
  const auto old_time = fs::last_write_time(kData + "/mushroom.off") - std::chrono::hours(1);
  fs::last_write_time(out("b.ply"), old_time);
  const auto a_time = fs::last_write_time(out("a.ply"));
  const RunResult r = batch("--skip-existing --results " + shell_quote(out("r.jsonl")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const std::vector<nlohmann::json> results = read_results(out("r.jsonl"));
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0]["status"], "skipped");
  EXPECT_EQ(results[1]["status"], "ok");
  EXPECT_EQ(fs::last_write_time(out("a.ply")), a_time);
  EXPECT_GT(fs::last_write_time(out("b.ply")), old_time);
}

TEST_F(BatchCli, SkipExistingSeesALayersFilesImages) {
  // A layers job's inputs include the images its layers file names: a
  // newer label makes the job run again; otherwise it is skipped.
  fs::copy_file(kData + "/label.png", dir / "label.png");
  std::ofstream(dir / "L.json")
      << R"({"layers":[{"proxy":{"kind":"cylinder","base":[0,0.15,0],"axis":[0,1,0],)"
         R"("radius":0.3,"height":0.4},"texture":"label.png"}]})";
  write_jobs({R"({"mesh":")" + kData + R"(/bottle.ply","layers":")" + out("L.json") +
              R"(","output":")" + out("b.ply") + R"("})"});
  ASSERT_EQ(batch("-q").exit_code, 0);
  RunResult r = batch("--skip-existing --results " + shell_quote(out("r1.jsonl")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_results(out("r1.jsonl"))[0]["status"], "skipped");
  fs::last_write_time(dir / "label.png",
                      fs::last_write_time(out("b.ply")) + std::chrono::seconds(10));
  r = batch("--skip-existing --results " + shell_quote(out("r2.jsonl")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_results(out("r2.jsonl"))[0]["status"], "ok");
}

TEST_F(BatchCli, BadValuesNameTheKey) {
  write_jobs({R"({"mesh":")" + kData + R"(/mushroom.off","proxy":"sphere","center":{"x":1}})"});
  const RunResult r = batch("");
  EXPECT_EQ(r.exit_code, 1);
  const std::vector<std::string> e = error_lines(r.err);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NE(e[0].find(":1: key 'center': {\"x\":1} is not a value"), std::string::npos) << e[0];
  const RunResult missing = run_texbake("batch " + shell_quote(out("none.jsonl")));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(error_lines(missing.err),
            std::vector<std::string>{out("none.jsonl") + ": no such file"});
}

TEST_F(BatchCli, BadLinesAreTheirOwnErrorsAndTheOthersRun) {
  const std::string mesh = kData + "/mushroom.off", texture = kData + "/earth.jpg";
  const std::string job =
      R"("mesh":")" + mesh + R"(","texture":")" + texture + R"(","proxy":"sphere","output":")";
  write_jobs({
      // 1: nested 100,000 deep (crashed); `{"mesh": ` is 9 characters, the
      // root level 1: the 128th '[' is level 129.
      R"({"mesh": )" + std::string(100000, '[') + std::string(100000, ']') + "}",
      // 2: a number beyond double's range (ended the whole batch).
      "{" + job + out("b.ply") + R"(","samples":1e999})",
      // 3: a good job, which runs.
      "{" + job + out("c.ply") + R"("})",
      // 4-6: values that look like flags are values: a mesh or texture file
      // named "--help" (printed the help and counted as ok).
      R"({"mesh":"--help","texture":")" + texture + R"(","proxy":"sphere","output":")" +
          out("d.ply") + R"("})",
      R"({"mesh":")" + mesh + R"(","texture":"--version","proxy":"sphere","output":")" +
          out("e.ply") + R"("})",
      // 6-10: keys that are no option of a job.
      R"({"help":true})",
      R"({"version":true})",
      "{" + job + out("h.ply") + R"(","quiet":true})",
      "{" + job + out("i.ply") + R"(","proxy-file":"p.json"})",
      "{" + job + out("j.ply") + R"(","linear":"yes"})",
      "{" + job + out("k.ply") + R"(","samples":true})",
  });
  const RunResult r = batch("--results " + shell_quote(out("results.jsonl")));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  // No help or version text: stdout is the summary line only.
  EXPECT_EQ(r.out.rfind("batch: 1 ok, 10 failed, 0 skipped, 0 not run of 11 jobs in ", 0), 0u)
      << r.out;
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << r.out;
  EXPECT_TRUE(fs::exists(out("c.ply")));
  for (const char* name : {"b", "d", "e", "h", "i", "j", "k"})
    EXPECT_FALSE(fs::exists(out(std::string(name) + ".ply"))) << name;

  const std::string jobs = (dir / "jobs.jsonl").string();
  const std::vector<std::string> want = {
      "1: key 'mesh' nests deeper than 128 levels (line 1, column 137)",
      "2: key 'samples' holds a number that is not finite (1e999 at line 1, column " +
          std::to_string(job.size() + out("b.ply").size() + 14) + ")",
      "4: --help: no such file",
      "5: --version: no such file",
      "6: key 'help' is not an option of texbake bake",
      "7: key 'version' is not an option of texbake bake",
      "8: key 'quiet' is the batch's option (texbake batch --quiet), not a job's",
      "9: key 'proxy-file' is not an option of texbake bake (did you mean 'proxy_file'?)",
      "10: key 'linear': \"yes\" is not true or false (a flag)",
      "11: key 'samples': true is not a value of the command line (the option takes one, not a "
      "flag's true or false)",
  };
  const std::vector<std::string> errors = error_lines(r.err);
  ASSERT_EQ(errors.size(), want.size()) << r.err;
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(errors[i], jobs + ":" + want[i]);

  // Every line has its result; bad JSON is a bad file (1), a bad key a
  // usage error (2), as for the single command.
  const std::vector<nlohmann::json> results = read_results(out("results.jsonl"));
  ASSERT_EQ(results.size(), 11u);
  const int exits[] = {1, 1, 0, 1, 1, 2, 2, 2, 2, 2, 2};
  for (int i = 0; i < 11; ++i) {
    EXPECT_EQ(results[i]["line"], i + 1);
    EXPECT_EQ(results[i]["exit"], exits[i]) << i + 1;
    EXPECT_EQ(results[i]["status"], i == 2 ? "ok" : "failed") << i + 1;
  }
  EXPECT_EQ(results[5]["error"], "key 'help' is not an option of texbake bake");
}

// Lines in a file, counted by their newlines.
std::size_t line_count(const fs::path& path) {
  const std::string text = slurp(path);
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

TEST_F(BatchCli, ResultsKeepEveryFinishedJobWhenTheBatchIsKilled) {
  constexpr int kJobs = 40;
  std::vector<std::string> lines;
  for (int i = 0; i < kJobs; ++i)
    lines.push_back(mushroom_job(out("m" + std::to_string(i) + ".ply")));
  const fs::path jobs = write_jobs(lines);
  // An older results file is emptied at the start.
  const fs::path results = dir / "results.jsonl";
  std::ofstream(results) << "old line 1\nold line 2\nold line 3\n";

  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (std::freopen("/dev/null", "w", stderr) == nullptr) ::_exit(127);
    ::execl(TEXBAKE_BINARY, "texbake", "batch", jobs.c_str(), "--results", results.c_str(),
            "--threads", "1", "-q", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Killed (SIGKILL: no clean-up of any kind) once two jobs have their line.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while ((slurp(results).rfind("old line", 0) == 0 || line_count(results) < 2) &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the batch ended before it was killed";

  // Every line is a whole result of a finished job, in order; every job
  // whose output exists has its line, but the one that may have been killed
  // between writing its output and its line.
  const std::vector<nlohmann::json> got = read_results(results);
  ASSERT_GE(got.size(), 2u);
  ASSERT_LT(got.size(), static_cast<std::size_t>(kJobs));
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i]["line"], i + 1);
    EXPECT_EQ(got[i]["status"], "ok");
    EXPECT_TRUE(fs::exists(out("m" + std::to_string(i) + ".ply")));
  }
  std::size_t outputs = 0;
  for (int i = 0; i < kJobs; ++i) outputs += fs::exists(out("m" + std::to_string(i) + ".ply"));
  EXPECT_GE(outputs, got.size());
  EXPECT_LE(outputs, got.size() + 1);
}

}  // namespace
