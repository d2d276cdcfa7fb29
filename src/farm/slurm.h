#pragma once
// A farm job (farm/farm_job.h) on Slurm: batch scripts for sbatch, their submission with
// afterok dependencies, and the job's state from squeue, sacct and the task records the scripts
// leave in the farm folder.
#include <map>
#include <string>
#include <vector>

#include "farm/farm_job.h"

namespace pluvia::farm {

struct SlurmOptions {
  std::string partition;                // "" : the cluster's default
  int cpusPerTask = 0;                  // 0: the cluster's default
  std::vector<std::string> sbatchArgs;  // more #SBATCH lines ("--time=2:00:00")
};

struct SlurmScript {
  std::string name;  // "prepare.sbatch"
  std::string text;
};

// prepare.sbatch, render.sbatch (a job array, one task per chunk) and, for a movie,
// assemble.sbatch; then submit.sh, which submits them in order with afterok dependencies.
std::vector<SlurmScript> slurmScripts(const FarmJob& job, const SlurmOptions& options);

// The job ids of a submitted farm job ("" where a job was not submitted). A render task
// resubmitted (`pluvia farm resubmit`) runs under another array job: `renderTasks` maps its
// chunk index to that job's id.
struct SlurmJobIds {
  std::string prepare, render, assemble;
  std::map<int, std::string> renderTasks;
  // The array job chunk `index` last ran under.
  std::string renderJobOf(int index) const;
};

// Writes the scripts, farm.json and the logs/ and tasks/ folders into job.farmDir.
void writeSlurmFarmFolder(const FarmJob& job, const std::vector<SlurmScript>& scripts);
// Submits the scripts in job.farmDir through `sbatch` (found on PATH; SLURM_CONF and the rest
// of the environment pass to it), each job after the previous one's success, and records the
// ids in jobs.json. Throws pluvia::Error with sbatch's message when a submission fails.
SlurmJobIds submitSlurm(const FarmJob& job);

// `pluvia farm status`: every job and array task of the farm job in job.farmDir, with its
// state (from the task records, squeue, and sacct where accounting is on), and the failed tasks
// with their frames and log paths.
struct FarmStatus {
  std::string text;
  int failed = 0;
  int timedOut = 0;       // of the failed, those stopped at their job's time limit
  bool finished = false;  // every job done, successfully or not
  // What failed or went missing (left the queue without a record), for `farm resubmit`.
  bool prepareFailed = false, assembleFailed = false;
  std::vector<int> failedChunks;
};
FarmStatus slurmStatus(const std::string& farmDir);

// `pluvia farm resubmit`: submits again only what failed or went missing in the farm job in
// `farmDir`, once every job of it has ended: the failed render tasks as one array job of those
// indices (their frames rendered with --skip-existing, so a timed-out chunk keeps what it
// wrote), then the assembly after them; a failed prepare resubmits the whole job. Their task
// records are removed first, and jobs.json records the new ids. Returns a line saying what was
// submitted ("" when nothing failed). Throws pluvia::Error while a job still runs.
std::string resubmitSlurm(const std::string& farmDir);

}  // namespace pluvia::farm
