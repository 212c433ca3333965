// tricot::mpi::World in a build without MPI (-DTRICOT_MPI=OFF): always one process.
#include "tricot/mpi/world.hpp"

namespace tricot::mpi {

struct World::Impl {};

std::string Traffic::brief_report() const { return "mpi: not in this build (-DTRICOT_MPI=OFF)"; }

World::World() = default;
World::~World() = default;
void World::lead(ident::Objective&) {}
void World::serve(const std::function<const ident::Objective*()>&) {}
Traffic World::traffic() const { return {}; }

}  // namespace tricot::mpi
