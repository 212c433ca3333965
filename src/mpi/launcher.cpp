// What an MPI launcher (or Slurm) tells a process in its environment, read without MPI (both builds).
#include <cstdlib>
#include <string>

#include "tricot/core/error.hpp"

#include "tricot/mpi/world.hpp"

namespace tricot::mpi {

namespace {

int env_int(std::initializer_list<const char*> names, int fallback) {
  for (const char* name : names)
    if (const char* v = std::getenv(name)) {
      try {
        return std::stoi(v);
      } catch (const std::exception&) {
        return fallback;
      }
    }
  return fallback;
}

}  // namespace

// SLURM_PROCID last: under a plain `srun -n N` (no MPI) only task 0 prints, e.g. the refusal below.
int launcher_rank() { return env_int({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"}, 0); }
int launcher_size() {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") && !std::getenv("PMIX_RANK") &&
      !std::getenv("PMI_RANK"))
    return 1;
  return env_int({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}, 0);
}

int slurm_step_tasks() {
  // srun sets SLURM_STEP_NUM_TASKS for every task of a step; a batch script has SLURM_NTASKS (the
  // job's) but no step: one process, whatever the allocation. An older srun without the step's
  // count still sets SLURM_STEP_ID beside SLURM_NTASKS.
  if (std::getenv("SLURM_STEP_NUM_TASKS")) return env_int({"SLURM_STEP_NUM_TASKS"}, 1);
  if (std::getenv("SLURM_STEP_ID")) return env_int({"SLURM_NTASKS"}, 1);
  return 1;
}

void refuse_duplicated_tasks(int world_size) {
  const int tasks = slurm_step_tasks();
  if (world_size != 1 || tasks <= 1) return;
  const std::string n = std::to_string(tasks);
  throw InputError(Location{"", 0, "mpi"},
                   "Slurm started " + n +
                       " tasks of tricot and no MPI world joins them: each would run the whole "
                       "identification into the same folder",
                   "SLURM_STEP_NUM_TASKS=" + n + ", 1 MPI process",
                   "mpirun -np " + n + " inside the allocation, srun --mpi=pmix -n " + n + ", or one task: srun -n 1");
}

}  // namespace tricot::mpi
