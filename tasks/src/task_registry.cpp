// The task registry: adding a control law is one entry here.
#include "predvs/predictors/registry.h"
#include "predvs/tasks/ibvs_broyden_task.h"
#include "predvs/tasks/ibvs_task.h"
#include "predvs/tasks/reference_filtering_task.h"
#include "predvs/tasks/vsc_task.h"
#include "predvs/tasks/vtc_task.h"
#include "predvs/tasks/task.h"

namespace predvs {
namespace {

using Tasks = Registry<Task, const Params&, const TaskContext&>;

const Tasks& tasks() {
  static const Tasks table(
      "task", {
                  {{"ibvs", "classic IBVS of image points through ViSP's vpServo (any robot via its camera Jacobian)"},
                   Tasks::factory<IbvsTask>()},
                  {{"ibvs-broyden",
                    "uncalibrated IBVS on an online RLS / Broyden Jacobian, switchable delay compensation (paper 002)"},
                   Tasks::factory<IbvsBroydenTask>()},
                  {{"vsc", "sliding-mode point servoing: exponential reaching law, boundary layer, scheduled gain (paper 000)"},
                   Tasks::factory<VscTask>()},
                  {{"vtc", "visual tracking law u = B_i^-1 (K_g X_e - Xdot_t) for a unicycle with a tilt camera (paper 001)"},
                   Tasks::factory<VtcTask>()},
                  {{"sr-lf-ibvs", "IBVS on (x, y, Z) points once per frame, command held for the frame (paper 003)"}, Tasks::factory<SrLfIbvsTask>()},
                  {{"sr-hf-ibvs", "IBVS on (x, y, Z) points every base period on the latest frame (paper 003)"}, Tasks::factory<SrHfIbvsTask>()},
                  {{"sr-lf-ekfs-ibvs", "IBVS to the EKF/RTS-filtered reference, once per frame (paper 003 Alg. 4)"}, Tasks::factory<SrLfEkfsIbvsTask>()},
                  {{"sr-hf-ekfs-ibvs", "IBVS to the EKF/RTS-filtered reference, every base period (paper 003 Alg. 4)"}, Tasks::factory<SrHfEkfsIbvsTask>()},
                  {{"dr-ekfs-ibvs", "dual-rate KF + dual-rate EKF/RTS reference + one command per base period (paper 003 Alg. 1-5)"}, Tasks::factory<DrEkfsIbvsTask>()},
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
