// The options of a bake job as one table (SPEC section 12): each option's
// key (a batch line's key, a Python keyword), command-line flag, type,
// default, range, the bakes it applies to and its help text. The table
// drives every client: `texbake bake` registers its flags from it, a batch
// line and Python's texbake.run_job give their values by key, and all of
// them become a Job through job_from_settings, which validates them with one
// set of messages (naming the command line's flag).
//
//   std::vector<texbake::JobSetting> s = {{"mesh", "bunny.ply"},
//                                         {"texture", "earth.jpg"},
//                                         {"proxy", "sphere"},
//                                         {"output", "bunny.glb"},
//                                         {"samples", "8"}};
//   texbake::Expected<texbake::Job> job = texbake::job_from_settings(s);
//   if (job) texbake::JobResult r = texbake::run_job(*job);
//
// And many jobs at once: run_batch runs a list of jobs (each a JSON object
// of the same keys), reports each as it ends (and appends its line to a
// results file, flushed), and returns what each did.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "job.h"  // its sibling, in the source tree and installed

namespace texbake {

// The bakes, by what projects (a job's kind, by its inputs) and its target.
// An option's `bakes` is a mask of these.
namespace bakes {
inline constexpr unsigned kProxyVertex = 1u << 0;   // an image through a proxy
inline constexpr unsigned kProxyAtlas = 1u << 1;    //
inline constexpr unsigned kCameraVertex = 1u << 2;  // a photo through a camera proxy_file
inline constexpr unsigned kCameraAtlas = 1u << 3;   //
inline constexpr unsigned kPhotosVertex = 1u << 4;  // calibrated photos (cameras)
inline constexpr unsigned kPhotosAtlas = 1u << 5;   //
inline constexpr unsigned kLayersVertex = 1u << 6;  // a layers file
inline constexpr unsigned kLayersAtlas = 1u << 7;   //
inline constexpr unsigned kProxy = kProxyVertex | kProxyAtlas;
inline constexpr unsigned kCamera = kCameraVertex | kCameraAtlas;
inline constexpr unsigned kPhotos = kPhotosVertex | kPhotosAtlas;
inline constexpr unsigned kLayers = kLayersVertex | kLayersAtlas;
inline constexpr unsigned kVertex = kProxyVertex | kCameraVertex | kPhotosVertex | kLayersVertex;
inline constexpr unsigned kAtlas = kProxyAtlas | kCameraAtlas | kPhotosAtlas | kLayersAtlas;
inline constexpr unsigned kAll = kVertex | kAtlas;
}  // namespace bakes

enum class JobOptionType {
  kPath,     // a file or folder
  kFlag,     // true or false (the command line's flag without a value)
  kInteger,  // a whole number in `range`
  kNumber,   // a finite number
  kVec3,     // x,y,z
  kCorners,  // x,y,z;x,y,z;x,y,z;x,y,z
  kChoice,   // one of the names in `range` ("a|b|c")
  kText,     // a keyword or a value (`range` says which: "fill|project|R,G,B[,A]")
};

struct JobOption {
  std::string_view key;         // "u_axis": a batch line's key, a Python keyword
  std::string_view flag;        // "--u-axis": the command line's long flag
  std::string_view short_flag;  // "-o" or ""
  JobOptionType type;
  std::string_view value_name;  // the value in --help: "N", "X,Y,Z", "" for a flag
  // The value the option takes when it is not given, as the command line
  // would take it ("2048", "area", "fill"; a flag's is "false"), or
  // "V (vertex), W (atlas)" when the targets' differ: the one default of the
  // command line, a batch line and Python (job_option_default). Words that
  // are not a value of the option ("by the output", "fitted to the mesh",
  // "all cores") say how the job works the default out; "" when there is
  // none (or the option is required).
  std::string_view default_text;
  std::string_view range;  // "1 .. 65536", "bilinear|area|ewa", ""
  unsigned bakes;          // the bakes it applies to (texbake::bakes)
  std::string_view help;   // the command line's --help text
  // Why it does not apply to the bakes outside `bakes`, when that needs
  // saying ("" for the bake's own reason).
  std::string_view not_here = "";
};

// Every option of a bake job, in the command line's --help order: the
// mesh (the command line's positional MESH), the inputs, the output, the
// proxy's geometry (mapping/proxy_schema.h's parameters), the target and
// the atlas, the lookup, the photos, the layers, the report and threads.
std::span<const JobOption> job_options();

// The option with this key, or nullptr.
const JobOption* find_job_option(std::string_view key);

// The default of `option` for a bake of `target` as the command line would
// take the value ("16", "bilinear", "false"), from its default_text; ""
// when the default is worked out by the job (a default_text in words, or
// a path's) or there is none. A job that does not give the option takes
// this value (job_from_settings), as Python's calls do.
std::string job_option_default(const JobOption& option, JobTarget target);

// One option's value as text, as the command line takes it ("8", "1,0,0",
// "sphere"; a flag "true" or "false").
struct JobSetting {
  std::string key;
  std::string value;
};

// The job the settings describe, every value and combination checked before
// any file is read, except a proxy_file, which is read to know whether it
// holds a camera. Errors (kInvalidArgument / kUnsupported: exit 2; reading
// the proxy file: kIo / kParse, exit 1) name the option by its flag, as the
// command line's do: an unknown key ("key 'x' is not an option of texbake
// bake"), a key given twice, a bad value ("--samples 0 is out of range (1 ..
// 65536)"), an option that does not apply to the bake ("--size applies to
// --target atlas only (...)", "--filter does not apply to --cameras (...)"),
// a missing input ("--texture is required ..."). The job's progress,
// on_warning and on_note are left empty.
Expected<Job> job_from_settings(std::span<const JobSetting> settings);

// A JSON object of the keys above (a batch line, Python's keywords) as
// settings: a string as it is, a number as JSON prints it, true or false for
// a flag (false: the option is not given), an array of numbers "x,y,z", an
// array of arrays of numbers "x,y,z;x,y,z;..." (corners). Errors
// (kInvalidArgument or the strict parse's kParse, mesh_io/json_strict.h:
// nested deeper than 128 levels, a number not finite, a key twice) name the
// key; `source` starts a parse error's message ("" for none).
Expected<std::vector<JobSetting>> job_settings_from_json(std::string_view object,
                                                         const std::string& source = "");

// ---- Many jobs (texbake batch) ----

// One job of a batch: its line number in the jobs file (1-based; its index
// + 1 for a list) and its JSON object.
struct BatchJob {
  std::size_t line = 0;
  std::string json;
};

struct BatchJobResult {
  std::size_t line = 0;
  std::string status;  // "ok", "failed" or "skipped"
  JobResult result;    // the job's (for "failed" before it ran: its error only)
  std::vector<std::filesystem::path> outputs;  // the files the job writes (or would)
  std::string json;  // its line of the results file: line, status, exit, error,
                     // warnings, outputs, target, counts, timings, seconds
};

struct BatchOptions {
  // The jobs file: an input of every job, so no job may write it ("" if none).
  std::filesystem::path manifest;
  // The results file (emptied at the start; each job's `json` appended and
  // flushed as the job ends, so a batch that is killed keeps the record of
  // the jobs it finished; "" for none): an output of every job.
  std::filesystem::path results;
  bool fail_fast = false;      // stop at the first failing job
  bool skip_existing = false;  // skip a job whose outputs exist and are not older than its inputs
  int threads = 0;             // the threads of a job without "threads" (0: all cores)
  // Called as each job ends (e.g. to print a line). May be empty.
  std::function<void(const BatchJobResult&)> on_job_end;
  // What the jobs share (JobCache, texbake/job.h): null, one for this batch.
  std::shared_ptr<JobCache> cache;
};

struct BatchResult {
  std::optional<Error> error;        // the batch's own: the results file cannot be written
  std::vector<BatchJobResult> jobs;  // the jobs run (or skipped), in order
  std::size_t ok = 0, failed = 0, skipped = 0, not_run = 0;
  double seconds = 0;
  bool ok_all() const { return !error && failed == 0; }
};

// Runs the jobs in order (job_settings_from_json, job_from_settings,
// run_job): a job's error is its own and the others run, unless fail_fast.
// No job may write the manifest or the results file (check_job_files).
BatchResult run_batch(std::span<const BatchJob> jobs, const BatchOptions& options = {});

// The file names of a job, for check_job_files, job_inputs and job_outputs.
JobFileNames job_file_names(const Job& job);

}  // namespace texbake
