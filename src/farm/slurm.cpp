#include "farm/slurm.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "util/error.h"
#include "util/fs.h"
#include "util/printable.h"
#include "util/subprocess.h"

namespace pluvia::farm {
namespace stdfs = std::filesystem;

// How long before a job's time limit Slurm warns its script (#SBATCH --signal).
constexpr int kTimeLimitWarningSeconds = 60;

namespace {

// A value on an #SBATCH line: sbatch reads the line itself (no shell), splitting at blanks
// unless the value is in double quotes. A control character (a newline would end the
// directive and start a command line) or a double quote cannot be written there: refused.
std::string directiveValue(const std::string& what, const std::string& value) {
  for (const unsigned char c : value) {
    if (c < 0x20 || c == 0x7f || c == '"')
      throw UsageError(fmt::format("{} '{}' holds a {}, which a Slurm #SBATCH line cannot carry: "
                                   "use a name without it",
                                   what, printable(value),
                                   c == '"' ? "double quote" : "control character (a newline?)"),
                       {"farm"});
  }
  return value.find_first_of(" \t") == std::string::npos ? value : "\"" + value + "\"";
}

std::string header(const FarmJob& job, const SlurmOptions& options, const std::string& jobName,
                   const std::string& logName) {
  std::string text = "#!/bin/bash\n";
  text += fmt::format("#SBATCH --job-name={}\n", directiveValue("the job name", jobName));
  text += fmt::format(
      "#SBATCH --output={}\n",
      directiveValue("--farm-dir", (stdfs::path(job.farmDir) / "logs" / logName).string()));
  text += fmt::format("#SBATCH --chdir={}\n", directiveValue("the working folder", job.workingDir));
  if (!options.partition.empty())
    text +=
        fmt::format("#SBATCH --partition={}\n", directiveValue("--partition", options.partition));
  if (options.cpusPerTask > 0)
    text += fmt::format("#SBATCH --cpus-per-task={}\n", options.cpusPerTask);
  // Slurm signals the script (B:) with USR1 a minute before the time limit, so that it can
  // stop the command cleanly and record a time-out, not a failure (recordedRun()).
  text += fmt::format("#SBATCH --signal=B:USR1@{}\n", kTimeLimitWarningSeconds);
  for (const std::string& arg : options.sbatchArgs)
    text += fmt::format("#SBATCH {}\n", directiveValue("--sbatch-arg", arg));
  return text;
}

// Runs `command`, then records its exit code, the host, why it ended and the log in
// tasks/RECORD.status, for `pluvia farm status` to list failed tasks where Slurm keeps no
// accounting: "exit" (it ended by itself), "timeout" (Slurm's USR1 before the time limit,
// header()) or "signal" (scancel, preemption: a SIGTERM). The command runs in the background
// so that the script's traps run at once and pass a SIGTERM on to it (pluvia stops after its
// current frame and removes its partial files); the loop waits until it has really ended. The
// log's folder is quoted for the shell and only its name, which holds Slurm's variables, is
// expanded.
std::string recordedRun(const FarmJob& job, const std::string& command, const std::string& record,
                        const std::string& logName) {
  const std::string logs = shellQuote((stdfs::path(job.farmDir) / "logs").string());
  return fmt::format(
      "why=exit\n"
      "trap 'why=timeout; kill -TERM \"$pid\" 2>/dev/null' USR1\n"
      "trap 'why=signal; kill -TERM \"$pid\" 2>/dev/null' TERM\n"
      "{} &\n"
      "pid=$!\n"
      "wait \"$pid\"\n"
      "code=$?\n"
      "while kill -0 \"$pid\" 2>/dev/null; do wait \"$pid\"; code=$?; done\n"
      "printf '%s %s %s %s\\n' \"$code\" \"$(hostname)\" \"$why\" {}/\"{}\" > {}/\"{}.status\"\n"
      "exit $code\n",
      command, logs, logName, shellQuote((stdfs::path(job.farmDir) / "tasks").string()), record);
}

// The output's name in the job names squeue shows; any character sbatch or a terminal could
// misread (a blank, a quote, a control character) as "_".
std::string jobLabel(const FarmJob& job) {
  std::string label = stdfs::path(job.output.path).stem().stem().string();
  for (char& c : label)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return label;
}

}  // namespace

std::vector<SlurmScript> slurmScripts(const FarmJob& job, const SlurmOptions& options) {
  const std::string label = jobLabel(job);
  std::vector<SlurmScript> scripts;
  // A comment: a newline in a name must not end it (printable() escapes control characters).
  std::string intro =
      fmt::format("# pluvia farm job: {} -> {}, frames {}-{}\n", printable(job.input),
                  printable(job.output.path), job.firstFrame, job.lastFrame);
  // The colour config the submitting shell named: a node with another $OCIO (or none) would
  // render in another colour space.
  if (!job.ocioConfig.empty()) intro += "export OCIO=" + shellQuote(job.ocioConfig) + "\n";

  scripts.push_back(
      {"prepare.sbatch",
       header(job, options, "pluvia-prepare-" + label, "prepare-%j.log") + intro +
           "# The per-clip analysis, once, into the shared cache.\n" +
           recordedRun(job, prepareCommand(job), "prepare", "prepare-${SLURM_JOB_ID}.log")});

  const int chunks = chunkCount(job);
  std::string render = header(job, options, "pluvia-render-" + label, "render-%A_%a.log");
  // A requeued task appends to its log: the failed try's messages stay readable.
  render += fmt::format("#SBATCH --array=0-{}\n#SBATCH --requeue\n#SBATCH --open-mode=append\n",
                        chunks - 1);
  render += intro;
  render += fmt::format(
      "# Task i renders frames {} + i x {} on, {} at most; --skip-existing keeps the frames a\n"
      "# requeued task already wrote.\n"
      "FIRST=$(( {} + SLURM_ARRAY_TASK_ID * {} ))\n"
      "LAST=$(( FIRST + {} ))\n"
      "if [ \"$LAST\" -gt {} ]; then LAST={}; fi\n",
      job.firstFrame, job.chunkFrames, job.chunkFrames, job.firstFrame, job.chunkFrames,
      job.chunkFrames - 1, job.lastFrame, job.lastFrame);
  render += recordedRun(job, renderCommand(job, "$FIRST-$LAST"), "render-${SLURM_ARRAY_TASK_ID}",
                        "render-${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}.log");
  scripts.push_back({"render.sbatch", render});

  if (isMovieJob(job)) {
    scripts.push_back(
        {"assemble.sbatch",
         header(job, options, "pluvia-assemble-" + label, "assemble-%j.log") + intro +
             "# The chunks' frames encoded into the movie.\n" +
             recordedRun(job, assembleCommand(job), "assemble", "assemble-${SLURM_JOB_ID}.log")});
  }

  std::string submit =
      "#!/bin/bash\n" + intro +
      "# Submits the jobs, each after the success of the one before (what `pluvia farm slurm\n"
      "# --submit` does).\nset -euo pipefail\ncd " +
      shellQuote(job.farmDir) +
      "\nprepare=$(sbatch --parsable prepare.sbatch | cut -d';' -f1)\n"
      "render=$(sbatch --parsable --dependency=afterok:$prepare render.sbatch | cut -d';' -f1)\n";
  if (isMovieJob(job))
    submit +=
        "assemble=$(sbatch --parsable --dependency=afterok:$render assemble.sbatch | cut -d';' "
        "-f1)\necho \"prepare $prepare render $render assemble $assemble\"\n";
  else
    submit += "echo \"prepare $prepare render $render\"\n";
  scripts.push_back({"submit.sh", submit});
  return scripts;
}

namespace {

// A farm folder is pluvia's own: new, empty, or an earlier farm job's (its farm.json). Anything
// else may be the user's files, which rewriting the folder would delete or mix with the job's.
void refuseForeignFarmFolder(const stdfs::path& dir) {
  std::error_code ec;
  for (const char* sub : {"logs", "tasks"}) {
    if (stdfs::is_symlink(dir / sub, ec))
      throw UsageError(fmt::format("--farm-dir {}: {} is a symbolic link; a farm folder's {} must "
                                   "be its own folder (choose a new --farm-dir)",
                                   dir.string(), (dir / sub).string(), sub),
                       {"farm", {}, (dir / sub).string()});
  }
  if (!stdfs::is_directory(dir, ec) || stdfs::is_empty(dir, ec) ||
      stdfs::exists(dir / "farm.json", ec))
    return;
  throw UsageError(fmt::format("--farm-dir {} holds files but no farm.json: it is not a pluvia "
                               "farm folder, and pluvia would overwrite them (choose a new or "
                               "empty folder)",
                               dir.string()),
                   {"farm", {}, dir.string()});
}

bool isTaskRecord(const stdfs::path& file) {
  return file.extension() == ".status";
}

}  // namespace

void writeSlurmFarmFolder(const FarmJob& job, const std::vector<SlurmScript>& scripts) {
  const stdfs::path dir = job.farmDir;
  refuseForeignFarmFolder(dir);
  for (const char* sub : {"logs", "tasks"}) {
    std::error_code ec;
    stdfs::create_directories(dir / sub, ec);
    if (ec)
      throw Error(
          fmt::format("cannot create the farm folder {}: {}", (dir / sub).string(), ec.message()),
          {"farm", {}, dir.string()});
  }
  // A farm folder is for one job: the task records of an earlier one would be read as this one's.
  for (const auto& entry : stdfs::directory_iterator(dir / "tasks"))
    if (isTaskRecord(entry.path())) stdfs::remove(entry.path());
  std::error_code ignored;
  stdfs::remove(dir / "jobs.json", ignored);
  for (const SlurmScript& script : scripts) {
    fs::writeTextFile(dir / script.name, script.text);
    stdfs::permissions(dir / script.name, stdfs::perms::owner_exec | stdfs::perms::group_exec,
                       stdfs::perm_options::add);
  }
  fs::writeTextFile(dir / "farm.json", farmJobJson(job));
}

namespace {

std::string submitOne(const FarmJob& job, const std::string& script, const std::string& after,
                      const std::string& array = "") {
  std::vector<std::string> argv{"sbatch", "--parsable"};
  if (!after.empty()) argv.push_back("--dependency=afterok:" + after);
  if (!array.empty()) argv.push_back("--array=" + array);  // over the script's own #SBATCH line
  argv.push_back((stdfs::path(job.farmDir) / script).string());
  const ProcessResult result = runProcess(argv);
  std::string id = result.output.substr(0, result.output.find_first_of(";\n"));
  if (result.exitCode != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    throw Error(
        fmt::format("sbatch {} failed (exit {}): {}", script, result.exitCode, result.output),
        {"farm", {}, (stdfs::path(job.farmDir) / script).string()});
  return id;
}

void writeJobIds(const stdfs::path& dir, const SlurmJobIds& ids) {
  nlohmann::json tasks = nlohmann::json::object();
  for (const auto& [index, id] : ids.renderTasks) tasks[std::to_string(index)] = id;
  const nlohmann::json record = {{"scheduler", "slurm"},
                                 {"prepare", ids.prepare},
                                 {"render", ids.render},
                                 {"assemble", ids.assemble},
                                 {"render_tasks", tasks}};
  fs::writeTextFile(dir / "jobs.json", record.dump(2) + "\n");
}

SlurmJobIds readJobIds(const stdfs::path& dir, const std::string& farmDir) {
  const stdfs::path jobsPath = dir / "jobs.json";
  if (!stdfs::exists(jobsPath))
    throw Error(fmt::format("the farm job in {} was not submitted (no jobs.json): run {} or "
                            "`pluvia farm slurm ... --submit`",
                            farmDir, (dir / "submit.sh").string()),
                {"farm", {}, farmDir});
  SlurmJobIds ids;
  try {
    fs::requireRegularFile(jobsPath, "the farm's job ids");
    const nlohmann::json json = nlohmann::json::parse(fs::readTextFile(jobsPath));
    ids = {json.at("prepare"), json.at("render"), json.at("assemble"), {}};
    if (json.contains("render_tasks"))
      for (const auto& [index, id] : json.at("render_tasks").items())
        ids.renderTasks[std::stoi(index)] = id.get<std::string>();
  } catch (const std::exception& e) {
    throw Error(fmt::format("{} is unreadable: {}", jobsPath.string(), e.what()),
                {"farm", {}, jobsPath.string()});
  }
  return ids;
}

void requireSbatch(const std::string& farmDir) {
  if (!programAvailable("sbatch"))
    throw Error("sbatch is not on PATH: submit from a Slurm login node, or run " +
                    (stdfs::path(farmDir) / "submit.sh").string() + " on one",
                {"farm", {}, farmDir});
}

}  // namespace

std::string SlurmJobIds::renderJobOf(int index) const {
  const auto again = renderTasks.find(index);
  return again == renderTasks.end() ? render : again->second;
}

SlurmJobIds submitSlurm(const FarmJob& job) {
  requireSbatch(job.farmDir);
  SlurmJobIds ids;
  const auto save = [&] { writeJobIds(job.farmDir, ids); };
  // Each id is recorded as soon as it is known, so a failed later submission leaves the earlier
  // jobs findable (by `pluvia farm status`, and to scancel).
  ids.prepare = submitOne(job, "prepare.sbatch", "");
  save();
  ids.render = submitOne(job, "render.sbatch", ids.prepare);
  save();
  if (isMovieJob(job)) {
    ids.assemble = submitOne(job, "assemble.sbatch", ids.render);
    save();
  }
  return ids;
}

namespace {

struct UnitState {
  std::string state;   // "COMPLETED", "FAILED (exit 1)", "PENDING (Dependency)" ...
  std::string detail;  // host and log
  bool failed = false;
  bool timedOut = false;  // stopped at the job's time limit (also counted as failed)
  bool done = false;
};

// squeue's view of a job (and its array's tasks, expanded): id -> "STATE (reason)". Empty when
// the job has left the queue.
std::map<std::string, std::string> queued(const std::string& jobId) {
  std::map<std::string, std::string> states;
  if (jobId.empty()) return states;
  const ProcessResult r = runProcess({"squeue", "-h", "-r", "-j", jobId, "-o", "%i|%T|%r"});
  if (r.exitCode != 0) return states;  // "Invalid job id": purged from the queue
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    const size_t a = line.find('|'), b = line.rfind('|');
    if (a == std::string::npos || a == b) continue;
    const std::string reason = line.substr(b + 1);
    states[line.substr(0, a)] = line.substr(a + 1, b - a - 1) +
                                (reason.empty() || reason == "None" ? "" : " (" + reason + ")");
  }
  return states;
}

// sacct's view (id -> "STATE exit CODE") where accounting is on; empty where it is off.
std::map<std::string, std::string> accounted(const std::vector<std::string>& jobIds) {
  std::map<std::string, std::string> states;
  std::string ids;
  for (const auto& id : jobIds)
    if (!id.empty()) ids += (ids.empty() ? "" : ",") + id;
  if (ids.empty() || !programAvailable("sacct")) return states;
  const ProcessResult r =
      runProcess({"sacct", "-n", "-P", "-X", "-j", ids, "-o", "JobID,State,ExitCode"});
  if (r.exitCode != 0) return states;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    const size_t a = line.find('|'), b = line.rfind('|');
    if (a == std::string::npos || a == b) continue;
    states[line.substr(0, a)] = line.substr(a + 1, b - a - 1) + " exit " + line.substr(b + 1);
  }
  return states;
}

// A file's text for a one-line message: its first 60 bytes, control characters and bytes
// outside ASCII as '?', so nothing in it can move the terminal.
std::string printable(const std::string& text) {
  std::string out = text.substr(0, 60);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  return text.size() > 60 ? out + "..." : out;
}

UnitState unitState(const std::string& id, const std::map<std::string, std::string>& queue,
                    const std::map<std::string, std::string>& accounting,
                    const stdfs::path& record) {
  UnitState unit;
  if (id.empty()) {
    unit.state = "not submitted";
    unit.done = true;
    return unit;
  }
  if (auto q = queue.find(id); q != queue.end()) {
    unit.state = q->second;
    return unit;
  }
  if (stdfs::exists(record)) {
    fs::requireRegularFile(record, "the task record");
    const std::string text = fs::readTextFile(record);
    std::istringstream fields(text);
    int code = -1;
    // "CODE HOST WHY LOG": the log last, since its path may hold blanks; a record of an older
    // pluvia has no WHY ("CODE HOST LOG"), and ended by itself.
    std::string host, why, log;
    unit.done = true;
    const bool read = bool(fields >> code >> host >> why);
    std::getline(fields >> std::ws, log);
    if (why != "exit" && why != "timeout" && why != "signal") {
      log = why + (log.empty() ? "" : " " + log);
      why = "exit";
    }
    if (!read || log.empty()) {
      // Not what recordedRun() writes (exit code, host, why, log): never counted as a success.
      unit.failed = true;
      unit.state = "UNREADABLE task record";
      unit.detail = fmt::format("{} reads '{}'", record.string(), printable(text));
      return unit;
    }
    unit.failed = code != 0;
    unit.timedOut = unit.failed && why == "timeout";
    unit.state = code == 0 ? "COMPLETED"
                 : unit.timedOut
                     ? fmt::format("TIMEOUT (stopped at the job's time limit, exit {})", code)
                 : why == "signal" ? fmt::format("CANCELLED (stopped by a signal, exit {})", code)
                                   : fmt::format("FAILED (exit {})", code);
    unit.detail = fmt::format("on {}, log {}", host, log);
    return unit;
  }
  unit.done = true;
  if (auto a = accounting.find(id); a != accounting.end()) {
    unit.state = a->second;
    unit.failed = a->second.rfind("COMPLETED", 0) != 0;
    unit.timedOut = a->second.rfind("TIMEOUT", 0) == 0;
    return unit;
  }
  // Left the queue without running its script to the end: cancelled, killed, or its node lost.
  unit.state = "GONE (not in squeue, no task record: cancelled or killed?)";
  unit.failed = true;
  return unit;
}

}  // namespace

FarmStatus slurmStatus(const std::string& farmDir) {
  const stdfs::path dir = farmDir;
  const stdfs::path jobsPath = dir / "jobs.json";
  if (!stdfs::exists(dir / "farm.json"))
    throw Error(fmt::format("{} holds no pluvia farm job (no farm.json)", farmDir),
                {"farm", {}, farmDir});
  fs::requireRegularFile(dir / "farm.json", "the farm job");
  const FarmJob job =
      farmJobFromJson(fs::readTextFile(dir / "farm.json"), (dir / "farm.json").string());
  const SlurmJobIds ids = readJobIds(dir, farmDir);

  std::vector<std::string> jobIds = {ids.prepare, ids.render, ids.assemble};
  for (const auto& [index, id] : ids.renderTasks)
    if (std::find(jobIds.begin(), jobIds.end(), id) == jobIds.end()) jobIds.push_back(id);
  std::map<std::string, std::string> queue;
  for (const std::string& id : jobIds)
    for (auto& [k, v] : queued(id)) queue[k] = v;
  const auto accounting = accounted(jobIds);

  FarmStatus status;
  status.finished = true;
  std::string failedList;
  const auto row = [&](const std::string& what, bool named, const std::string& id,
                       const std::string& frames, const std::string& record) -> bool {
    UnitState unit = unitState(id, queue, accounting, dir / "tasks" / (record + ".status"));
    status.text +=
        fmt::format("  {:<9} {:<10} {:<12} {}{}\n", named ? what : "", id.empty() ? "-" : id,
                    frames, unit.state, unit.detail.empty() ? "" : ", " + unit.detail);
    status.finished = status.finished && unit.done;
    if (unit.failed) {
      ++status.failed;
      status.timedOut += unit.timedOut ? 1 : 0;
      failedList += fmt::format("  {} {} {}: {}{}\n", what, id, frames, unit.state,
                                unit.detail.empty() ? "" : ", " + unit.detail);
    }
    return unit.failed;
  };
  status.text =
      fmt::format("farm job {}: {} -> {}, frames {}-{} in {} chunks of {}\n", farmDir, job.input,
                  job.output.path, job.firstFrame, job.lastFrame, chunkCount(job), job.chunkFrames);
  status.prepareFailed = row("prepare", true, ids.prepare, "", "prepare");
  for (int i = 0; i < chunkCount(job); ++i) {
    const auto [first, last] = chunkFrames(job, i);
    const std::string render = ids.renderJobOf(i);
    const std::string taskId = render.empty() ? "" : fmt::format("{}_{}", render, i);
    if (row("render", i == 0, taskId, fmt::format("frames {}-{}", first, last),
            fmt::format("render-{}", i)))
      status.failedChunks.push_back(i);
  }
  if (isMovieJob(job)) status.assembleFailed = row("assemble", true, ids.assemble, "", "assemble");
  if (status.failed && status.timedOut == status.failed)
    status.text += fmt::format(
        "timed out ({}; their frames so far are kept: `pluvia farm resubmit {}` (with a longer "
        "#SBATCH --time in render.sbatch) renders only the rest):\n{}",
        status.failed, farmDir, failedList);
  else if (status.failed)
    status.text += fmt::format(
        "failed ({}{}):\n{}", status.failed,
        status.timedOut ? fmt::format(", {} timed out", status.timedOut) : "", failedList);
  else if (status.finished)
    status.text += "all done\n";
  return status;
}

std::string resubmitSlurm(const std::string& farmDir) {
  const FarmStatus status = slurmStatus(farmDir);
  if (!status.finished)
    throw Error(fmt::format("the farm job in {} still runs: resubmit once every job has ended "
                            "(`pluvia farm status {} --wait`)",
                            farmDir, farmDir),
                {"farm", {}, farmDir});
  if (status.failed == 0) return "";
  requireSbatch(farmDir);
  const stdfs::path dir = farmDir;
  const FarmJob job =
      farmJobFromJson(fs::readTextFile(dir / "farm.json"), (dir / "farm.json").string());
  const auto removeRecord = [&](const std::string& name) {
    std::error_code ignored;
    stdfs::remove(dir / "tasks" / (name + ".status"), ignored);
  };
  if (status.prepareFailed) {  // the chunks read its cache: everything again
    for (const auto& entry : stdfs::directory_iterator(dir / "tasks"))
      if (isTaskRecord(entry.path())) stdfs::remove(entry.path());
    const SlurmJobIds ids = submitSlurm(job);
    return fmt::format("the whole job again (its prepare failed): prepare {}, render {}{}",
                       ids.prepare, ids.render,
                       ids.assemble.empty() ? "" : ", assemble " + ids.assemble);
  }
  SlurmJobIds ids = readJobIds(dir, farmDir);
  std::string submitted;
  if (!status.failedChunks.empty()) {
    std::string array;
    for (const int index : status.failedChunks) {
      array += (array.empty() ? "" : ",") + std::to_string(index);
      removeRecord(fmt::format("render-{}", index));
    }
    const std::string render = submitOne(job, "render.sbatch", "", array);
    for (const int index : status.failedChunks) ids.renderTasks[index] = render;
    writeJobIds(dir, ids);
    submitted = fmt::format("render {} (chunks {})", render, array);
  }
  // The movie is assembled again after any chunk rendered again, or when it alone failed.
  if (isMovieJob(job) && (status.assembleFailed || !status.failedChunks.empty())) {
    removeRecord("assemble");
    const std::string after =
        status.failedChunks.empty() ? "" : ids.renderJobOf(status.failedChunks.front());
    ids.assemble = submitOne(job, "assemble.sbatch", after);
    writeJobIds(dir, ids);
    submitted += (submitted.empty() ? "" : ", ") + fmt::format("assemble {}", ids.assemble);
  }
  return submitted;
}

}  // namespace pluvia::farm
