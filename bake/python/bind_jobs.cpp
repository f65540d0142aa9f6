// Whole jobs, as `texbake bake` and `texbake batch` run them: the option
// table (texbake/job_options.h), run_job over a JSON object of the table's
// keys (the Python half builds it from keyword arguments), and run_batch
// over a list of such objects. The job reads, bakes and writes its files
// itself; the result is the library's JobResult as a dict.
#include "bake/python/common.h"
#include "texbake/job_options.h"

namespace texbake::python {

namespace {

const char* type_name(JobOptionType type) {
  switch (type) {
    case JobOptionType::kPath:
      return "path";
    case JobOptionType::kFlag:
      return "flag";
    case JobOptionType::kInteger:
      return "integer";
    case JobOptionType::kNumber:
      return "number";
    case JobOptionType::kVec3:
      return "vec3";
    case JobOptionType::kCorners:
      return "corners";
    case JobOptionType::kChoice:
      return "choice";
    case JobOptionType::kText:
      return "text";
  }
  return "";
}

// The bakes of a mask, as "proxy vertex", "photos atlas", ...
py::list bakes_list(unsigned mask) {
  static const std::pair<unsigned, const char*> kBakes[] = {
      {bakes::kProxyVertex, "proxy vertex"},   {bakes::kProxyAtlas, "proxy atlas"},
      {bakes::kCameraVertex, "camera vertex"}, {bakes::kCameraAtlas, "camera atlas"},
      {bakes::kPhotosVertex, "photos vertex"}, {bakes::kPhotosAtlas, "photos atlas"},
      {bakes::kLayersVertex, "layers vertex"}, {bakes::kLayersAtlas, "layers atlas"}};
  py::list out;
  for (const auto& [bit, name] : kBakes) {
    if (mask & bit) out.append(name);
  }
  return out;
}

py::list options_list() {
  py::list out;
  for (const JobOption& o : job_options()) {
    py::dict d;
    d["key"] = std::string(o.key);
    d["flag"] = std::string(o.flag);
    d["type"] = type_name(o.type);
    d["value_name"] = std::string(o.value_name);
    d["default"] = std::string(o.default_text);
    // The value it takes when not given, per target (None: worked out by the job).
    py::dict values;
    for (const auto& [target, name] :
         {std::pair{JobTarget::kVertex, "vertex"}, std::pair{JobTarget::kAtlas, "atlas"}}) {
      const std::string v = job_option_default(o, target);
      values[name] = v.empty() ? py::object(py::none()) : py::object(py::str(v));
    }
    d["defaults"] = values;
    d["range"] = std::string(o.range);
    d["bakes"] = bakes_list(o.bakes);
    d["help"] = std::string(o.help);
    out.append(d);
  }
  return out;
}

py::list paths_list(const std::vector<std::filesystem::path>& paths) {
  py::list out;
  for (const std::filesystem::path& p : paths) out.append(p.string());
  return out;
}

// A job's result: outputs, warnings, notes, fitted, report (JSON text),
// summary, seconds.
py::dict job_dict(const JobResult& r) {
  py::dict d;
  d["outputs"] = paths_list(r.outputs);
  d["warnings"] = r.warnings;
  d["notes"] = r.notes;
  d["fitted"] = r.fitted;
  d["report"] = r.report;
  d["summary"] = r.summary;
  d["seconds"] = r.seconds;
  return d;
}

py::dict run_job_json(const std::string& json, py::object progress) {
  // Parsing a line is quick: under the GIL, which an error needs to raise.
  Job job = check(job_from_settings(check(job_settings_from_json(json, ""))));
  PyRun run(py::int_(0), std::move(progress));
  job.progress = run.run.progress;
  JobResult result;
  {
    py::gil_scoped_release release;
    result = run_job(job);
  }
  run.rethrow();
  if (result.error) raise(*result.error);
  return job_dict(result);
}

py::dict run_batch_json(const std::vector<std::string>& jobs, py::handle results,
                        py::handle manifest, bool fail_fast, bool skip_existing,
                        py::handle threads) {
  BatchOptions options;
  if (!results.is_none()) options.results = path_arg(results, "results");
  if (!manifest.is_none()) options.manifest = path_arg(manifest, "manifest");
  options.fail_fast = fail_fast;
  options.skip_existing = skip_existing;
  const long long n = int_arg(threads, "--threads");
  check(check_range("--threads", n, 0, kMaxThreads));
  options.threads = static_cast<int>(n);
  std::vector<BatchJob> lines;
  for (std::size_t i = 0; i < jobs.size(); ++i) lines.push_back({i + 1, jobs[i]});
  BatchResult batch;
  {
    py::gil_scoped_release release;
    batch = run_batch(lines, options);
  }
  if (batch.error) raise(*batch.error);
  py::list results_list;
  for (const BatchJobResult& r : batch.jobs) results_list.append(r.json);
  py::dict d;
  d["jobs"] = results_list;
  d["ok"] = batch.ok;
  d["failed"] = batch.failed;
  d["skipped"] = batch.skipped;
  d["not_run"] = batch.not_run;
  d["seconds"] = batch.seconds;
  return d;
}

}  // namespace

void bind_jobs(py::module_& m) {
  m.def("job_options", &options_list);
  m.def("run_job", &run_job_json, py::arg("json"), py::arg("progress") = py::none());
  m.def("run_batch", &run_batch_json, py::arg("jobs"), py::arg("results") = py::none(),
        py::arg("manifest") = py::none(), py::arg("fail_fast") = false,
        py::arg("skip_existing") = false, py::arg("threads") = 0);
}

}  // namespace texbake::python
