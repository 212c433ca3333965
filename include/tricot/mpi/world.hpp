// The processes of `mpirun -np N tricot identify …` (issue 15): rank 0 runs Levenberg–Marquardt and
// everything else; the other ranks evaluate their share of the objective's tests at the parameters
// rank 0 sends, until it says stop. This header does not include MPI: a build without it
// (-DTRICOT_MPI=OFF) has the same class, always one process.
#pragma once

#include <exception>
#include <functional>
#include <memory>
#include <string>

#include "tricot/ident/objective.hpp"

namespace tricot::mpi {

/// What rank 0 measured of the split (for `--verbose` and docs/validation.md).
struct Traffic {
  int rounds = 0;              ///< evaluations spread over the ranks
  int jacobian_rounds = 0;     ///< of which with the Jacobian
  double bytes_sent = 0;       ///< by rank 0: the parameters, to every other rank
  double bytes_received = 0;   ///< by rank 0: the other ranks' test values
  double largest_message = 0;  ///< bytes, the largest one received
  double mpi_seconds = 0;      ///< rank 0's time in MPI calls (sends, receives: waits included)
  double local_seconds = 0;    ///< rank 0's time on its own tests
  /// Σ over rounds of (round's wall − its slowest rank's compute time): the cost of spreading the
  /// tests (messages, packing, wake-ups), load imbalance excluded.
  double overhead_seconds = 0;
  std::string brief_report() const;  ///< one line
};

/// This process's rank and the number of processes as an MPI launcher's environment gives them
/// (Open MPI's OMPI_COMM_WORLD_RANK/SIZE, PMIx's PMIX_RANK, PMI's PMI_RANK/PMI_SIZE): 0 and 1 without
/// one. Read before MPI starts, and in a build without MPI: the CLI prints its errors on rank 0 only.
int launcher_rank();
int launcher_size();  ///< 0 when the launcher does not say (PMIx)

/// The tasks Slurm started for this job step (SLURM_STEP_NUM_TASKS, set by srun; SLURM_NTASKS
/// where an older srun sets SLURM_STEP_ID without it); 1 outside Slurm and in a batch script itself
/// (one process, whatever the allocation's --ntasks).
int slurm_step_tasks();
/// Throws InputError (key `mpi`, exit 2) when Slurm started several tasks (slurm_step_tasks() > 1)
/// and `world_size` is 1: a plain `srun -n N` without an MPI plugin (MpiDefault=none), or an MPI
/// library that does not speak the plugin's PMI, where each task would run the whole identification
/// into the same folder and all would exit 0.
void refuse_duplicated_tasks(int world_size);

/// MPI_COMM_WORLD, when this process was started by an MPI launcher (mpirun, srun) and the build has
/// MPI; otherwise one process (rank 0 of 1) and every method is a no-op. In a build without MPI,
/// started by a launcher with more than one process, the constructor throws InputError (key `mpi`):
/// the ranks would each run the whole identification into the same folder. In both builds it throws
/// refuse_duplicated_tasks's error when Slurm started several tasks that no MPI world joins.
class World {
 public:
  World();
  /// Rank 0: releases the other ranks (waiting first for their ready message if lead() was never
  /// reached, e.g. after an error), then every rank finalizes MPI. Never throws.
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Rank 0, once its objective is built: waits for every rank's ready message and throws the
  /// first failed rank's error (its exit code, "rank R: " before its message); then spreads
  /// `objective`'s tests over the ranks (round-robin: test t on rank t mod N). Nothing with one rank.
  void lead(ident::Objective& objective);
  /// Ranks > 0: builds the objective with `build` (same project as rank 0; an exception is caught
  /// and sent to rank 0, which reports it), then evaluates its tests at every request until rank 0
  /// says stop. An exception while serving aborts the whole run (MPI_Abort), after one line on
  /// stderr: rank 0 would otherwise wait forever.
  void serve(const std::function<const ident::Objective*()>& build);

  /// Rank 0: the split's figures so far (zero before lead()).
  Traffic traffic() const;

 private:
  struct Impl;
  int rank_ = 0, size_ = 1;
  std::shared_ptr<Impl> impl_;
};

}  // namespace tricot::mpi
