// The task registry: adding a control law is one entry here.
#include "predvs/predictors/registry.h"
#include "predvs/tasks/ibvs_task.h"
#include "predvs/tasks/task.h"

namespace predvs {
namespace {

using Tasks = Registry<Task, const Params&, const TaskContext&>;

const Tasks& tasks() {
  static const Tasks table(
      "task", {
                  {{"ibvs", "classic IBVS of image points through ViSP's vpServo (any robot via its camera Jacobian)"},
                   Tasks::factory<IbvsTask>()},
              });
  return table;
}

}  // namespace

const std::vector<RegistryInfo>& taskRegistry() { return tasks().infos(); }
bool isTask(const std::string& name) { return tasks().has(name); }
std::unique_ptr<Task> makeTask(const std::string& name, const Params& params, const TaskContext& context) {
  auto task = tasks().make(name, params, context);
  params.requireAllUsed("task '" + name + "'");
  return task;
}

}  // namespace predvs
