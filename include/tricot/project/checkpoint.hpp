// DIR/checkpoint.json of `tricot identify`: ident::Checkpoint (LM's progress, names and scales) plus a
// fingerprint of the data and the model, rewritten after every accepted LM step (with its phase: LM,
// stability test, done); `--resume` reads it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tricot/fem/law.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/ident/objective.hpp"

namespace tricot::project {

inline constexpr const char* kCheckpointFile = "checkpoint.json";

/// FNV-1a over the measured data, their factors, each parameter's name, start and scale, the law's
/// coefficients and every model's reference mesh: a checkpoint belongs to these ([identify] may change
/// between runs). 16 hex digits.
std::string fingerprint(const ident::Objective& objective, const fem::Law& law,
                        const std::vector<fem::TestModel>& models);

/// Writes `c` and the fingerprint atomically.
void write_checkpoint(const std::filesystem::path& file, const ident::Checkpoint& c, const std::string& fingerprint);
/// Reads a checkpoint. FileError when there is none; InputError (key `fingerprint`) when it belongs to
/// other data or another model, or when the file is not a tricot checkpoint.
ident::Checkpoint read_checkpoint(const std::filesystem::path& file, const std::string& fingerprint);

}  // namespace tricot::project
