// SPDX-License-Identifier: Apache-2.0
// `mirage rig FILE`: a vehicle's lidars from one rig file (docs/rig.md) — every sensor rendered
// and paced in one process from one pose stream on one sensor clock. With a `control` section
// the rig waits for a Modbus controller's commands (docs/control.md). `--check` prints the
// effective configuration and opens nothing.
#include <cstdio>

#include "commands.hpp"
#include "keep_awake_option.hpp"
#include "rig_control.hpp"
#include "rig_plan.hpp"
#include "rig_run.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {

void register_rig(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "rig", "Run a vehicle's lidars from a rig file: one scene, one trajectory, one clock");
    struct Opts {
        std::string file, duration;
        bool check = false, no_status = false, keep_awake = false;
        int rt_priority = 0;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("file", o->file, "Rig file (YAML; docs/rig.md)")->required();
    cmd->add_flag("--check", o->check,
                  "Validate the rig file and print the effective configuration; send nothing");
    cmd->add_option("--duration", o->duration, "Seconds to run (overrides the rig file's)");
    cmd->add_flag("--no-status", o->no_status, "No status line on stderr");
    cmd->add_option("--rt-priority", o->rt_priority,
                    "Send from a SCHED_FIFO thread at this priority (1-99; needs CAP_SYS_NICE)")
        ->check(CLI::Range(0, 99));
    add_keep_awake_flag(*cmd, o->keep_awake);
    cmd->callback([o] {
        const rig::RigConfig config = rig::load_rig(o->file);
        // The whole process, a controlled rig's idle waits included (docs/time.md §5).
        const auto awake = keep_cpus_awake(o->keep_awake && !o->check, "rig");
        if (config.control.enabled && !o->check) {
            run_controlled_rig(config, {o->duration, !o->no_status, o->rt_priority, awake.get()});
            return;
        }
        RigPlan plan = plan_rig(config, o->duration);
        if (o->check) {
            std::printf("%s", describe(plan).c_str());
            return;
        }
        RigRunOptions ro;
        ro.status_line = !o->no_status;
        ro.rt_priority = o->rt_priority;
        ro.awake = awake.get();
        ro.stop = &install_stop_signal();
        if (plan.config.nav.empty())
            run_rig(plan, ro);
        else
            run_rig_live(plan, ro);
    });
}

}  // namespace mirage::hil
