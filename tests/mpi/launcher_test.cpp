// tricot::mpi's launcher environment and the refusal of duplicated Slurm tasks (src/mpi/launcher.cpp,
// src/mpi/world.cpp; issue 34): `srun -n 2 tricot identify` without an MPI plugin starts two
// processes that no MPI world joins; each would run the whole identification into the same folder.
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <optional>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/mpi/world.hpp"

namespace tricot::mpi {
namespace {

using Vars = std::map<std::string, std::string>;

// Sets the launcher's and Slurm's variables for one test and puts the process's own back after it.
class Environment {
 public:
  explicit Environment(const Vars& set) {
    for (const char* name : kNames) {
      const char* v = std::getenv(name);
      saved_[name] = v ? std::optional<std::string>(v) : std::nullopt;
      ::unsetenv(name);
    }
    for (const auto& [name, value] : set) ::setenv(name.c_str(), value.c_str(), 1);
  }
  ~Environment() {
    for (const auto& [name, value] : saved_)
      if (value) ::setenv(name.c_str(), value->c_str(), 1);
      else ::unsetenv(name.c_str());
  }
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

 private:
  static constexpr const char* kNames[] = {
      "SLURM_STEP_NUM_TASKS", "SLURM_STEP_ID", "SLURM_NTASKS", "SLURM_PROCID", "OMPI_COMM_WORLD_RANK",
      "OMPI_COMM_WORLD_SIZE", "PMIX_RANK",     "PMI_RANK",     "PMI_SIZE"};
  std::map<std::string, std::optional<std::string>> saved_;
};

TEST(SlurmStepTasks, IsOneOutsideSlurm) {
  Environment env(Vars{});
  EXPECT_EQ(slurm_step_tasks(), 1);
}

TEST(SlurmStepTasks, IsTheStepsTaskCountUnderSrun) {
  Environment env(Vars{{"SLURM_STEP_NUM_TASKS", "4"}, {"SLURM_STEP_ID", "0"}, {"SLURM_NTASKS", "8"}});
  EXPECT_EQ(slurm_step_tasks(), 4);  // the step's, not the job's
}

TEST(SlurmStepTasks, IsOneInABatchScriptWhateverTheAllocation) {
  // sbatch --ntasks=8 runs the script once: SLURM_NTASKS is the job's, no step.
  Environment env(Vars{{"SLURM_NTASKS", "8"}});
  EXPECT_EQ(slurm_step_tasks(), 1);
}

TEST(SlurmStepTasks, FallsBackOnTheJobsTasksInAStepWithoutItsCount) {
  Environment env(Vars{{"SLURM_STEP_ID", "0"}, {"SLURM_NTASKS", "3"}});
  EXPECT_EQ(slurm_step_tasks(), 3);
}

TEST(LauncherRank, IsSlurmsTaskIdUnderAPlainSrun) {
  Environment env(Vars{{"SLURM_PROCID", "1"}, {"SLURM_STEP_NUM_TASKS", "2"}});
  EXPECT_EQ(launcher_rank(), 1);  // only task 0 prints the refusal
  EXPECT_EQ(launcher_size(), 1);  // srun without an MPI plugin is no MPI launch
}

TEST(LauncherRank, IsMpisRankBeforeSlurms) {
  Environment env(Vars{{"SLURM_PROCID", "0"}, {"OMPI_COMM_WORLD_RANK", "3"}, {"OMPI_COMM_WORLD_SIZE", "4"}});
  EXPECT_EQ(launcher_rank(), 3);
  EXPECT_EQ(launcher_size(), 4);
}

TEST(World, RefusesSeveralSlurmTasksThatNoMpiWorldJoins) {
  Environment env(
      Vars{{"SLURM_STEP_NUM_TASKS", "2"}, {"SLURM_STEP_ID", "0"}, {"SLURM_NTASKS", "2"}, {"SLURM_PROCID", "0"}});
  try {
    World world;
    FAIL() << "two Slurm tasks in a world of " << world.size() << " were not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exit_code(), ExitCode::usage);
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("mpi: Slurm started 2 tasks of tricot and no MPI world joins them", 0), 0u) << what;
    EXPECT_NE(what.find("got SLURM_STEP_NUM_TASKS=2, 1 MPI process"), std::string::npos) << what;
    EXPECT_NE(what.find("srun --mpi=pmix -n 2"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
  }
}

TEST(World, RunsOneSlurmTask) {
  Environment env(Vars{{"SLURM_STEP_NUM_TASKS", "1"}, {"SLURM_STEP_ID", "0"}, {"SLURM_NTASKS", "1"}});
  World world;
  EXPECT_EQ(world.size(), 1);
  EXPECT_EQ(world.rank(), 0);
}

TEST(World, RunsInABatchScriptOfSeveralTasks) {
  Environment env(Vars{{"SLURM_NTASKS", "2"}});
  World world;
  EXPECT_EQ(world.size(), 1);
}

}  // namespace
}  // namespace tricot::mpi
