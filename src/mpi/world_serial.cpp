// tricot::mpi::World in a build without MPI (-DTRICOT_MPI=OFF): always one process.
#include "tricot/mpi/world.hpp"

#include "tricot/core/error.hpp"

namespace tricot::mpi {

struct World::Impl {};

std::string Traffic::brief_report() const { return "mpi: not in this build (-DTRICOT_MPI=OFF)"; }

World::World() {
  const int size = launcher_size();
  if (size != 1)
    throw InputError(Location{"", 0, "mpi"}, "this tricot was built without MPI (-DTRICOT_MPI=OFF)",
                     size > 1 ? std::to_string(size) + " processes" : "an MPI launch",
                     "one process: run it without mpirun, or build with -DTRICOT_MPI=ON");
  refuse_duplicated_tasks(1);
}
World::~World() = default;
void World::lead(ident::Objective&) {}
void World::serve(const std::function<const ident::Objective*()>&) {}
Traffic World::traffic() const { return {}; }

}  // namespace tricot::mpi
