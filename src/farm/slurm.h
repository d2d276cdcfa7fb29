#pragma once
// A farm job (farm/farm_job.h) on Slurm: batch scripts for sbatch, their submission with
// afterok dependencies, and the job's state from squeue, sacct and the task records the scripts
// leave in the farm folder.
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

// The job ids of a submitted farm job ("" where a job was not submitted).
struct SlurmJobIds {
  std::string prepare, render, assemble;
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
};
FarmStatus slurmStatus(const std::string& farmDir);

}  // namespace pluvia::farm
