# Point particles (dpm, dpm-reference, immersed point): settling, granular
# gases, two-way and one-way coupling, dispersion, injection, the jet on a
# plate, crosschecks and ranks.
# Included from tests/CMakeLists.txt (validation/tests.cmake): test names,
# working folders and ${vcfg} are those of tests/.
coflow_validation(dpm_settling dpm_settling dpm_settling.yaml 1)
coflow_validation(dpm_granular_gas granular_gas dpm_granular_gas.yaml 1)
coflow_validation(dpm_granular_gas_bidisperse granular_gas dpm_granular_gas_bidisperse.yaml 1)
# A dense gas (alpha 0.05) where the mean collision time sets the step (eq. 4.15).
coflow_validation(dpm_granular_gas_dense granular_gas dpm_granular_gas_dense.yaml 1)
coflow_validation(dpm_vs_reference compare dpm_crosscheck.yaml 1 "particles.solver=dpm" "particles.solver=dpm-reference")
coflow_validation(dpm_two_way two_way dpm_two_way.yaml 2)
# The same at u_p(0) = 1 mm/s (Re_p 0.004): the drag factor is constant, as the
# closed form of eqs 5.4-5.5 assumes.
coflow_validation(dpm_two_way_stokes two_way dpm_two_way.yaml 2
  --set "particles.initial=[{lattice: {species: droplet, spacing: 0.1, region: {lower: [0.0, 0.0, 0.0], upper: [1.0, 1.0, 1.0]}, velocity: [0.001, 0.0, 0.0]}}]")
coflow_validation(dpm_dispersion dispersion dpm_dispersion.yaml 2)
coflow_validation(dpm_injection injection dpm_injection.yaml 1)
coflow_validation(dpm_jet_vs_reference compare dpm_jet_crosscheck.yaml 1
  "particles.solver=dpm run.output.collision_events=true" "particles.solver=dpm-reference run.output.collision_events=true")
# Point particles with one-way coupling: the fluid never feels them.
coflow_run_ranks(np ${vcfg}/dpm_two_way.yaml)
add_test(NAME validation.dpm_one_way
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/one_way.sh ${CMAKE_BINARY_DIR}/bin ${vcfg}/dpm_two_way.yaml
          ${CMAKE_CURRENT_BINARY_DIR}/val-dpm_one_way)
set_tests_properties(validation.dpm_one_way PROPERTIES LABELS "validation;mpi" PROCESSORS ${np})
# Granular jet on a plate (seed 003 §5.3): the plate is written by
# scripts/make_plate_stl.py (jet.sh).
set(jet ${CMAKE_CURRENT_LIST_DIR}/jet.sh)
function(coflow_jet name mode config procs plate)
  add_test(NAME validation.${name}
    COMMAND ${jet} ${name} ${CMAKE_BINARY_DIR}/bin ${CMAKE_CURRENT_BINARY_DIR}/val-${name} ${mode}
            ${vcfg}/${config} ${plate} ${ARGN})
  set(runs ${ARGN})
  list(FILTER runs EXCLUDE REGEX "^--")
  string(REPLACE "@WALLS@" "" runs "${runs}")
  coflow_case_ranks(ranks ${vcfg}/${config} ${runs})
  set_tests_properties(validation.${name} PROPERTIES LABELS "validation;mpi" PROCESSORS ${ranks})
endfunction()
coflow_jet(dpm_jet_plate_no_pp jet dpm_jet_plate.yaml 1 - --set @WALLS@ --set particles.collision.enabled=false)
coflow_jet(dpm_jet_plate jet dpm_jet_plate.yaml 1 - --set @WALLS@)
# The same jet with the air computed by fv around the plate as an immersed
# body and coupled both ways (immersed.ibm.particles: point), to the first
# impacts: the air dragged along makes them faster than in still air.
# The full-size case shortened to 8 ms (the first impacts).
coflow_jet(dpm_jet_plate_fv jet ../cases/dpm_jet_plate_fv.yaml 1 - --set @WALLS@
  --set [=[immersed.ibm.bodies=[{"name":"plate","mesh":"@PLATE@"}]]=] --set particles.collision.enabled=false
  --set run.end_time=0.008 --set run.output.every=0.008)
coflow_jet(dpm_mesh_vs_reference compare dpm_jet_crosscheck.yaml 1
  "--size 0.02 --thickness 0.002 --cells 6 --center 0.025 0.025 0.02 --normal z --tilt 25"
  "particles.solver=dpm run.output.collision_events=true @WALLS@"
  "particles.solver=dpm-reference run.output.collision_events=true @WALLS@")
# A pair collision drives a particle into a thin mesh plate within the step:
# the rest of its path meets the plate and it comes back (before 2026-12-03
# it went through for good: z = 0.65 mm below the 1 mm plate), in dpm and
# dpm-reference alike.
coflow_validation(dpm_pair_into_mesh pair_into_mesh dpm_pair_into_mesh.yaml 1)
coflow_validation(dpm_pair_into_mesh_reference pair_into_mesh dpm_pair_into_mesh.yaml 1
  --set particles.solver=dpm-reference)
# Particles entering within a coupling window see the fluid at their inlet
# (its probes, sampled at the window's start): in a stream moving with them
# they keep its speed exactly (before 2026-12-04 they saw the fluid at rest
# until the next window and lost up to 0.22 m/s of 2), in dpm, dpm-reference
# and dpm on 3 ranks (rank 0 injects; the particles migrate with their
# sample).
coflow_validation(dpm_inlet_stream inlet_stream dpm_inlet_stream.yaml 1)
coflow_validation(dpm_inlet_stream_reference inlet_stream dpm_inlet_stream.yaml 1
  --set particles.solver=dpm-reference)
coflow_validation(dpm_inlet_stream_ranks_3 inlet_stream dpm_inlet_stream.yaml 2
  --set particles.ranks=3 --set particles.decomposition=[1,1,3])
# The same inlet into a stream of 1 m/s: the particles slow down, and on 3
# ranks (each migrating the step it enters) their states must be
# those of 1 rank bit for bit, which holds only if the inlet's sample
# migrates with them.
coflow_validation(dpm_inlet_stream_ranks_1_vs_3 compare dpm_inlet_stream.yaml 2
  "particles.ranks=1 fluid.analytic.velocity=[0,0,1]"
  "particles.ranks=3 particles.decomposition=[1,1,3] fluid.analytic.velocity=[0,0,1]")
# An inlet mostly covered by a resting sphere keeps up with its mass flow:
# a particle that finds no room is drawn 64 new places the next step (before
# 2026-12-04 the same 64 again: the inlet stalled for good, 0 of 50
# injected), in dpm and dpm-reference.
coflow_validation(dpm_inlet_blocked inlet_mass dpm_inlet_blocked.yaml 1)
coflow_validation(dpm_inlet_blocked_reference inlet_mass dpm_inlet_blocked.yaml 1
  --set particles.solver=dpm-reference)
# An inlet across a periodic face: entering particles at their images inside
# the box, clear of their neighbours' images (0.40 D overlaps before
# 2026-12-04), in dpm and dpm-reference, and on 3 ranks cut along x (the
# neighbours across the seam on rank 2) as on 1.
coflow_validation(dpm_inlet_periodic inlet_mass dpm_inlet_periodic.yaml 1)
coflow_validation(dpm_inlet_periodic_reference inlet_mass dpm_inlet_periodic.yaml 1
  --set particles.solver=dpm-reference)
coflow_validation(dpm_inlet_periodic_ranks_1_vs_3 compare dpm_inlet_periodic.yaml 2
  "particles.ranks=1" "particles.ranks=3 particles.decomposition=[3,1,1]")
coflow_validation(dpm_ranks_1_vs_4 compare dpm_crosscheck.yaml 2
  "particles.ranks=1 run.end_time=0.05 run.output.every=0.025"
  "particles.ranks=4 particles.decomposition=[2,2,1] run.end_time=0.05 run.output.every=0.025")
coflow_jet(dpm_jet_ranks_1_vs_3 compare dpm_jet_crosscheck.yaml 2
  "--size 0.02 --thickness 0.002 --cells 6 --center 0.025 0.025 0.02 --normal z --tilt 25"
  "particles.ranks=1 run.output.collision_events=true @WALLS@"
  "particles.ranks=3 particles.decomposition=[1,1,3] run.output.collision_events=true @WALLS@")
coflow_validation(dpm_grid_turbulence grid_turbulence dpm_grid_turbulence.yaml 2)
coflow_validation(dpm_grid_turbulence_ct026 grid_turbulence dpm_grid_turbulence.yaml 2 --set particles.dispersion.C_T=0.26)
coflow_validation(dpm_two_way_loaded two_way dpm_two_way_loaded.yaml 2)
# A window 5e-7 longer than two lattice steps (whole_steps accepts it to
# 1e-6): the fluid scales the particles' source to its steps' time, so the
# momentum balance stays at round-off (4.5e-7 without). 250 such windows (a
# given window must divide run.end_time).
coflow_validation(dpm_two_way_window_off_steps two_way dpm_two_way_loaded.yaml 2
  --set coupling.window=0.020029386433435707 --set run.end_time=5.007346608358927)
coflow_validation(dpm_two_way_layouts compare dpm_two_way_loaded.yaml 2
  "fluid.ranks=1 immersed.ranks=1 particles.ranks=1" "fluid.ranks=4 immersed.ranks=2 particles.ranks=4")
# Scattered particles: a cell's source sums many particles' spread impulses.
coflow_validation(dpm_two_way_scattered_layouts compare dpm_two_way_scattered.yaml 2
  "fluid.ranks=1 immersed.ranks=1 particles.ranks=1" "fluid.ranks=2 immersed.ranks=3 particles.ranks=2")
# Few particles: most rows of fluid cells hold no source; the fluid cut along
# x (its rows of 11 and 10 cells) against one rank.
coflow_validation(dpm_two_way_sparse_ranks compare dpm_two_way_sparse.yaml 2
  "fluid.ranks=1" "fluid.ranks=3 fluid.decomposition=[3,1,1] immersed.ranks=2 particles.ranks=2")
# Issue 19's case: point particles settling on a wall, two-way: runs, or stops
# naming the cause; with the remedy it names, runs to its end.
add_test(NAME validation.dpm_settling_on_wall
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/settling_on_wall.sh ${CMAKE_BINARY_DIR}/bin
          ${CMAKE_CURRENT_LIST_DIR}/settling_on_wall.yaml ${CMAKE_CURRENT_BINARY_DIR}/val-dpm_settling_on_wall)
set_tests_properties(validation.dpm_settling_on_wall PROPERTIES LABELS "validation;mpi" PROCESSORS 3)
# Its outlet remedy, two-way: the grains leaving through z- hand their
# window's impulse back to the fluid (departed records): 1 rank against 2
# fluid and 2 particle ranks, and dpm against dpm-reference.
set(sow ../../tests/validation/point_particles/settling_on_wall.yaml)
coflow_validation(dpm_outlet_two_way_ranks_1_vs_2 compare ${sow} 3
  "particles.boundaries.z-=outlet" "particles.boundaries.z-=outlet fluid.ranks=2 particles.ranks=2")
coflow_validation(dpm_outlet_two_way_vs_reference compare ${sow} 3
  "particles.boundaries.z-=outlet" "particles.boundaries.z-=outlet particles.solver=dpm-reference")
# docs/tutorial.md, steps 2 and 3 (step 1 is validation.tutorial_channel).
add_test(NAME validation.tutorial_particles
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/tutorial.sh ${CMAKE_BINARY_DIR}/bin ${PROJECT_SOURCE_DIR}/configs/tutorial
          ${CMAKE_CURRENT_BINARY_DIR}/val-tutorial_particles)
set_tests_properties(validation.tutorial_particles PROPERTIES LABELS "validation;mpi" PROCESSORS 3)
# The same dispersion on a computed carrier flow (issue 22): fv with k-epsilon
# feeds dpm's Langevin model; dpm writes series/dispersion.csv (eq. 5.24),
# compared with the model's moments in the k-epsilon decay the fluid carries.
coflow_validation(dpm_grid_turbulence_fv grid_turbulence_fv dpm_grid_turbulence_fv.yaml 3)
# Many ranks (issue 24): 16 in all, oversubscribed, against 1/1/1, with the
# lbm and the fv fluid.
coflow_validation(dpm_two_way_ranks_1_vs_16 compare dpm_two_way.yaml 2
  "fluid.ranks=1 immersed.ranks=1 particles.ranks=1" "fluid.ranks=8 immersed.ranks=4 particles.ranks=4")
coflow_validation(dpm_two_way_fv_ranks_1_vs_16 compare dpm_two_way_fv.yaml 2
  "fluid.ranks=1 immersed.ranks=1 particles.ranks=1" "fluid.ranks=8 immersed.ranks=4 particles.ranks=4")
# A checkpoint of dpm on 2 ranks (rank 0's particles first in the file)
# restarts dpm-reference on 1 rank bit for bit, its collision log too (before
# 2026-12-05 both variants kept the file's order after a restart, and
# dpm-reference logged such pairs with their ids the other way round).
coflow_validation(dpm_reference_restart_from_dpm_2_ranks restart_from dpm_granular_gas.yaml 2
  0.1 "particles.ranks=2 particles.decomposition=[1,2,1] run.end_time=0.2 run.output.every=0.2"
  "particles.solver=dpm-reference run.end_time=0.2 run.output.every=0.2")
