// Engine selection (see engine.hpp).
#include "replay/batch/engine.hpp"

#include "replay/batch/local_engine.hpp"
#include "replay/batch/process.hpp"
#include "replay/batch/slurm_engine.hpp"

namespace orthosonar::batch {

Result<std::unique_ptr<Engine>> make_engine(const std::string& name, const EngineOptions& options) {
  if (name == "local") return std::unique_ptr<Engine>(std::make_unique<LocalEngine>(options));
  if (name == "slurm") return std::unique_ptr<Engine>(std::make_unique<SlurmEngine>(options));
  return Error{"unknown batch engine '" + name + "' (engines: local, slurm)"};
}

std::string task_executable(const EngineOptions& options) {
  return options.executable.empty() ? self_executable() : options.executable;
}

}  // namespace orthosonar::batch
