// What an MPI launcher tells a process in its environment, read without MPI (both builds).
#include <cstdlib>
#include <string>

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

int launcher_rank() { return env_int({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}, 0); }
int launcher_size() {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") && !std::getenv("PMIX_RANK") &&
      !std::getenv("PMI_RANK"))
    return 1;
  return env_int({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}, 0);
}

}  // namespace tricot::mpi
