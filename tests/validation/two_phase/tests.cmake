# Two fluids by the colour-gradient model (seed 000 §2.3.4, lbm and
# lbm-reference) and interior solids: Laplace's law, contact angles, layered
# flow and relative permeabilities, colour mass, the voxelised sphere array's
# permeability, and the crosschecks of lbm against lbm-reference and of 1
# rank against 4.
# Included from tests/CMakeLists.txt (validation/tests.cmake).
# (JSON-style flow maps: the override lists split on spaces.)
set(drop2d [=[fluid.initial.phase=[{"fill":{"phase":"blue"}},{"sphere":{"centre":[0.048,0.048,0.0005],"phase":"red","radius":]=])
coflow_validation(two_phase_laplace_2d laplace two_phase_droplet_2d.yaml 1
  "${drop2d}0.016}}]" "${drop2d}0.020}}]" "${drop2d}0.024}}]")
# The half-disc starts at 90 degrees; the 90-degree drop starts at 66 (its
# centre 1 cm below the wall), so that each must move to its angle.
coflow_validation(two_phase_contact_angle_60 contact_angle two_phase_contact_angle.yaml 1
  --set fluid.two_phase.contact_angle=60)
coflow_validation(two_phase_contact_angle_90 contact_angle two_phase_contact_angle.yaml 1
  --set fluid.two_phase.contact_angle=90 --set
  [=[fluid.initial.phase=[{"fill":{"phase":"blue"}},{"sphere":{"centre":[0.06,-0.01,0.0005],"radius":0.027,"phase":"red"}}]]=])
coflow_validation(two_phase_contact_angle_120 contact_angle two_phase_contact_angle.yaml 1
  --set fluid.two_phase.contact_angle=120)
# The seed's wetting (seed 000 "Molhabilidade": a solid of fixed colour
# cos theta) at 60 degrees, where it holds the issue's 3 degrees (it misses
# by 9 at 120 and 14 at 150: docs/validation.md's plot).
coflow_validation(two_phase_contact_angle_seed_60 contact_angle two_phase_contact_angle.yaml 1
  --set fluid.two_phase.contact_angle=60 --set fluid.two_phase.wetting=seed)
# Layered flow between plates at viscosity ratios 10 and 1 (Yiotis et al. 2007).
coflow_validation(two_phase_layered_m10 layered two_phase_layered.yaml 1)
coflow_validation(two_phase_layered_m1 layered two_phase_layered.yaml 1 --set fluid.two_phase.viscosity_blue=1.0e-5)
# The voxelised sphere array (Zick & Homsy 1982) and, from the same run, the
# force on the interior solid (series/fluid_walls.csv, solid1): the fluid's
# momentum balance row to row, and at steady state the sphere carries the body
# force on the fluid. Then TRT's steady state at two relaxation times (a
# smaller array, 12 cells across).
coflow_validation(solids_sphere_array permeability+fluid_walls solids_sphere_array.yaml 2)
set(small_array "domain.cells=[16,16,16] domain.upper=[0.016,0.016,0.016] run.end_time=800 run.output.every=800 run.output.series_every=40 fluid.ranks=1")
coflow_validation(solids_sphere_array_tau tau_independence solids_sphere_array.yaml 1
  "${small_array} fluid.lbm.tau=0.6 fluid.solids=[{\"sphere\":{\"centre\":[0.008,0.008,0.008],\"radius\":0.006}}]"
  "${small_array} fluid.lbm.tau=1.5 fluid.solids=[{\"sphere\":{\"centre\":[0.008,0.008,0.008],\"radius\":0.006}}]")
# Crosschecks on a 3D case with walls, an interior solid, two viscosities and
# the geometric wetting: lbm against lbm-reference, 1 rank against 4 (the
# same bits), and the seed's wetting against lbm-reference too.
coflow_validation(two_phase_vs_reference compare two_phase_crosscheck_3d.yaml 1
  "fluid.solver=lbm" "fluid.solver=lbm-reference")
coflow_validation(two_phase_vs_reference_seed compare two_phase_crosscheck_3d.yaml 1
  "fluid.solver=lbm fluid.two_phase.wetting=seed fluid.lbm.collision=bgk"
  "fluid.solver=lbm-reference fluid.two_phase.wetting=seed fluid.lbm.collision=bgk")
coflow_validation(two_phase_ranks_1_vs_4 compare two_phase_crosscheck_3d.yaml 2
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[2,2,1]")
# The phase (rho_r - rho_b) / (rho_r + rho_b) as the colour field
# (fluid.two_phase.colour_field): the same crosschecks, the seed's wetting of
# grains (which colours them by eps cos(theta) then), and Laplace's law.
coflow_validation(two_phase_vs_reference_phase compare two_phase_crosscheck_3d.yaml 1
  "fluid.solver=lbm fluid.two_phase.colour_field=phase" "fluid.solver=lbm-reference fluid.two_phase.colour_field=phase")
coflow_validation(two_phase_ranks_1_vs_4_phase compare two_phase_crosscheck_3d.yaml 2
  "fluid.ranks=1 fluid.two_phase.colour_field=phase"
  "fluid.ranks=4 fluid.decomposition=[2,2,1] fluid.two_phase.colour_field=phase")
coflow_validation(two_phase_grains_vs_reference_seed_phase compare two_phase_grains_crosscheck.yaml 1
  "fluid.solver=lbm fluid.two_phase.wetting=seed fluid.lbm.collision=bgk fluid.two_phase.colour_field=phase"
  "fluid.solver=lbm-reference fluid.two_phase.wetting=seed fluid.lbm.collision=bgk fluid.two_phase.colour_field=phase")
coflow_validation(two_phase_laplace_2d_phase laplace two_phase_droplet_2d.yaml 1
  "${drop2d}0.016}}] fluid.two_phase.colour_field=phase" "${drop2d}0.020}}] fluid.two_phase.colour_field=phase"
  "${drop2d}0.024}}] fluid.two_phase.colour_field=phase")
# The same with the cuts along z (the solid box spans them).
coflow_validation(two_phase_grains_ranks_1_vs_4_z compare two_phase_grains_crosscheck.yaml 2
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[1,1,4]")
# Each colour's mass over 10^4 steps (in the 3D crosscheck case).
coflow_validation(two_phase_colour_mass colour_mass two_phase_crosscheck_3d.yaml 1
  --set run.end_time=1000.0 --set run.output.every=1000.0)
# Capillary filling of a slit (Washburn 1921, the displaced fluid's resistance kept).
coflow_validation(two_phase_washburn washburn two_phase_washburn.yaml 1)
# Faces that carry a phase: red injected through a velocity inlet (its mass
# grows at the inlet's flux), and the crosschecks with a pressure outlet
# (regularized), an outflow outlet, and the inlet on 4 ranks.
coflow_validation(two_phase_injection injection_phase two_phase_injection.yaml 1)
coflow_validation(two_phase_injection_vs_reference compare two_phase_injection.yaml 1
  "fluid.solver=lbm run.end_time=30.0 run.output.every=30.0"
  "fluid.solver=lbm-reference run.end_time=30.0 run.output.every=30.0")
coflow_validation(two_phase_outflow_vs_reference compare two_phase_injection.yaml 1
  "fluid.solver=lbm run.end_time=30.0 run.output.every=30.0 fluid.boundaries.x+={\"type\":\"outflow\"}"
  "fluid.solver=lbm-reference run.end_time=30.0 run.output.every=30.0 fluid.boundaries.x+={\"type\":\"outflow\"}")
coflow_validation(two_phase_injection_ranks_1_vs_4 compare two_phase_injection.yaml 2
  "fluid.ranks=1 run.end_time=60.0 run.output.every=60.0"
  "fluid.ranks=4 fluid.decomposition=[2,2,1] run.end_time=60.0 run.output.every=60.0")
# Open faces that meet with two fluids (since session 67): a stream of red
# alone through velocity faces on three sides carrying red, held exactly;
# the red inlet under an open top (a pressure face y+ meeting the inlet x-
# and the outlet x+), against lbm-reference and on 4 ranks.
coflow_validation(two_phase_open_corners uniform_stream lbm_open_corners.yaml 1
  --set "fluid.two_phase={\"surface_tension\":1.0e-6,\"beta\":0.7}"
  --set "fluid.initial={\"phase\":[{\"fill\":{\"phase\":\"red\"}}]}"
  --set fluid.boundaries.x-.phase=red --set fluid.boundaries.y-.phase=red --set fluid.boundaries.y+.phase=red)
set(tp_open_top "fluid.boundaries.y+={\"type\":\"pressure\",\"value\":0.0}")
coflow_validation(two_phase_open_top_vs_reference compare two_phase_injection.yaml 1
  "fluid.solver=lbm run.end_time=30.0 run.output.every=30.0 ${tp_open_top}"
  "fluid.solver=lbm-reference run.end_time=30.0 run.output.every=30.0 ${tp_open_top}")
coflow_validation(two_phase_open_top_ranks_1_vs_4 compare two_phase_injection.yaml 2
  "fluid.ranks=1 run.end_time=60.0 run.output.every=60.0 ${tp_open_top}"
  "fluid.ranks=4 fluid.decomposition=[2,2,1] run.end_time=60.0 run.output.every=60.0 ${tp_open_top}")
# The red inlet with a parabolic profile (since session 67).
coflow_validation(two_phase_injection_profile_vs_reference compare two_phase_injection.yaml 1
  "fluid.solver=lbm run.end_time=30.0 run.output.every=30.0 fluid.boundaries.x-.profile=parabolic"
  "fluid.solver=lbm-reference run.end_time=30.0 run.output.every=30.0 fluid.boundaries.x-.profile=parabolic")
coflow_validation(two_phase_injection_profile_ranks_1_vs_4 compare two_phase_injection.yaml 2
  "fluid.ranks=1 run.end_time=60.0 run.output.every=60.0 fluid.boundaries.x-.profile=parabolic"
  "fluid.ranks=4 fluid.decomposition=[2,2,1] run.end_time=60.0 run.output.every=60.0 fluid.boundaries.x-.profile=parabolic")
# One fluid with an interior solid and open faces.
coflow_validation(solids_channel_vs_reference compare solids_channel.yaml 1 "fluid.solver=lbm" "fluid.solver=lbm-reference")
coflow_validation(solids_channel_ranks_1_vs_4 compare solids_channel.yaml 2
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[2,2,1]")
# The interpolated bounce-back (fluid.lbm.bounce_back, Bouzidi et al. 2001):
# lbm against lbm-reference and 1 rank against 4 on the disc in the channel;
# two fluids and wetting at an off-grid sphere (3D); psm grains next to one;
# and the sphere array (Zick & Homsy 1982) with the sphere's true surface
# (its radius for phi = 0.216).
set(interpolated "fluid.lbm.bounce_back=interpolated")
coflow_validation(solids_channel_interpolated_vs_reference compare solids_channel.yaml 1
  "fluid.solver=lbm ${interpolated}" "fluid.solver=lbm-reference ${interpolated}")
coflow_validation(solids_channel_interpolated_ranks_1_vs_4 compare solids_channel.yaml 2
  "fluid.ranks=1 ${interpolated}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${interpolated}")
# The disc in the channel on D3Q19 one cell deep (periodic z: the links (±1,
# 0, ±1) stream in the plane, and the fractions and the central
# interpolation's second cell follow them), against lbm-reference and on 4 ranks.
set(flat_central "fluid.lbm.lattice=D3Q19 fluid.lbm.collision=trt fluid.lbm.bounce_back=central")
coflow_validation(solids_channel_central_flat_d3q19_vs_reference compare solids_channel.yaml 1
  "fluid.solver=lbm ${flat_central}" "fluid.solver=lbm-reference ${flat_central}")
coflow_validation(solids_channel_central_flat_d3q19_ranks_1_vs_4 compare solids_channel.yaml 2
  "fluid.ranks=1 ${flat_central}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${flat_central}")
# The box of the config and a sphere 0.3 of a link from the first fluid
# centres beside it and beside the wall y = 0, where the interpolation's
# second cell is solid or beyond the wall (half-way there).
set(offgrid_solids "fluid.solids=[{\"box\":{\"lower\":[0.004,0.0,0.0],\"upper\":[0.009,0.005,0.006],\"contact_angle\":120.0}},{\"sphere\":{\"centre\":[0.0125,0.0035,0.004],\"radius\":0.0027,\"contact_angle\":60.0}}]")
set(offgrid_sphere "${interpolated} ${offgrid_solids}")
coflow_validation(two_phase_interpolated_vs_reference compare two_phase_crosscheck_3d.yaml 1
  "fluid.solver=lbm ${offgrid_sphere}" "fluid.solver=lbm-reference ${offgrid_sphere}")
# Each colour's mass over 10^4 steps with the interpolated bounce-back at
# both solids: what the links take from a colour goes back into the cell's
# rest population.
coflow_validation(two_phase_interpolated_colour_mass colour_mass two_phase_crosscheck_3d.yaml 1
  --set run.end_time=1000.0 --set run.output.every=1000.0 --set ${interpolated} --set ${offgrid_solids})
coflow_validation(two_phase_interpolated_ranks_1_vs_4 compare two_phase_crosscheck_3d.yaml 2
  "fluid.ranks=1 ${offgrid_sphere}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${offgrid_sphere}")
set(grain_solids "fluid.solids=[{\"sphere\":{\"centre\":[0.0031,0.0047,0.0079],\"radius\":0.0033,\"contact_angle\":110.0}}]")
set(grain_sphere "${interpolated} ${grain_solids}")
coflow_validation(two_phase_grains_interpolated_vs_reference compare two_phase_grains_crosscheck.yaml 1
  "fluid.solver=lbm ${grain_sphere}" "fluid.solver=lbm-reference ${grain_sphere}")
coflow_validation(two_phase_grains_interpolated_ranks_1_vs_4 compare two_phase_grains_crosscheck.yaml 2
  "fluid.ranks=1 ${grain_sphere}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${grain_sphere}")
coflow_validation(solids_sphere_array_interpolated permeability+fluid_walls solids_sphere_array.yaml 2 --set ${interpolated}
  --set [=[fluid.solids=[{"sphere":{"centre":[0.016,0.016,0.016],"radius":0.011912}}]]=])
# The central linear interpolation (fluid.lbm.bounce_back: central, Ginzburg,
# Verhaeghe & d'Humieres 2008): the sphere array against Zick & Homsy and at
# two relaxation times (TRT: its wall does not move with tau); against
# lbm-reference (two fluids at the off-grid sphere and the box, psm grains),
# on 4 ranks, and each colour's mass.
set(central "fluid.lbm.bounce_back=central")
coflow_validation(solids_sphere_array_central permeability+fluid_walls solids_sphere_array.yaml 2 --set ${central}
  --set [=[fluid.solids=[{"sphere":{"centre":[0.016,0.016,0.016],"radius":0.011912}}]]=])
coflow_validation(solids_sphere_array_tau_central tau_independence solids_sphere_array.yaml 1
  "${small_array} ${central} fluid.lbm.tau=0.6 fluid.solids=[{\"sphere\":{\"centre\":[0.008,0.008,0.008],\"radius\":0.006}}]"
  "${small_array} ${central} fluid.lbm.tau=1.5 fluid.solids=[{\"sphere\":{\"centre\":[0.008,0.008,0.008],\"radius\":0.006}}]")
coflow_validation(two_phase_central_vs_reference compare two_phase_crosscheck_3d.yaml 1
  "fluid.solver=lbm ${central} ${offgrid_solids}" "fluid.solver=lbm-reference ${central} ${offgrid_solids}")
coflow_validation(two_phase_central_ranks_1_vs_4 compare two_phase_crosscheck_3d.yaml 2
  "fluid.ranks=1 ${central} ${offgrid_solids}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${central} ${offgrid_solids}")
coflow_validation(two_phase_central_colour_mass colour_mass two_phase_crosscheck_3d.yaml 1
  --set run.end_time=1000.0 --set run.output.every=1000.0 --set ${central} --set ${offgrid_solids})
coflow_validation(two_phase_grains_central_vs_reference compare two_phase_grains_crosscheck.yaml 1
  "fluid.solver=lbm ${central} ${grain_solids}" "fluid.solver=lbm-reference ${central} ${grain_solids}")
coflow_validation(two_phase_grains_central_ranks_1_vs_4 compare two_phase_grains_crosscheck.yaml 2
  "fluid.ranks=1 ${central} ${grain_solids}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${central} ${grain_solids}")
# Laplace in 3D (D3Q19), one droplet of 18 cells in a 56-cell box on 1 rank
# (2 ranks took 1.45x the core-seconds, 2026-12-06; the same bits)
# (the issue's 2 % needs R = 18: 5.7 % at 10 cells, 2.6 % at 14). tau = 1 at
# the same time step (the viscosity 5/3 of the 2D case's): the pressure waves
# of the start die faster, and 2000 steps give 1.45 % (tau = 0.8: 2.1 % after
# 2000 steps, 1.2 % after 3000). Laplace's law does not hold the viscosity.
coflow_validation(two_phase_laplace_3d laplace two_phase_droplet_2d.yaml 1
  [=[fluid.lbm.lattice=D3Q19 fluid.ranks=1 fluid.lbm.tau=1.0 fluid.viscosity=1.6666666666666667e-6 domain.cells=[56,56,56] domain.upper=[0.056,0.056,0.056] run.end_time=200.0 run.output.every=200.0 run.output.series_every=40.0 fluid.initial.phase=[{"fill":{"phase":"blue"}},{"sphere":{"centre":[0.028,0.028,0.028],"phase":"red","radius":0.018}}]]=])
# The fluid's force on the walls of the layered flow (two fluids; diagonal
# links at the periodic x faces): momentum balance row to row, and at steady
# state the walls carry the body force.
coflow_validation(two_phase_layered_walls fluid_walls two_phase_layered.yaml 1 --set fluid.two_phase.viscosity_blue=1.0e-5
  --set run.output.series_every=150.0)
# Wetted grains (partially saturated cells in two fluids): lbm against
# lbm-reference with geometric and the seed's wetting, 1 fluid rank against 4
# (the same bits), a free grain at a flat interface at 60, 90 and 120
# degrees (at 90 nothing moves: 500 steps), and the capillary bridge between two touching spheres.
coflow_validation(two_phase_grains_vs_reference compare two_phase_grains_crosscheck.yaml 1
  "fluid.solver=lbm" "fluid.solver=lbm-reference")
coflow_validation(two_phase_grains_vs_reference_seed compare two_phase_grains_crosscheck.yaml 1
  "fluid.solver=lbm fluid.two_phase.wetting=seed fluid.lbm.collision=bgk"
  "fluid.solver=lbm-reference fluid.two_phase.wetting=seed fluid.lbm.collision=bgk")
coflow_validation(two_phase_grains_ranks_1_vs_4 compare two_phase_grains_crosscheck.yaml 2
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[2,2,1]")
# Many ranks (issue 24): 16 in all, oversubscribed.
coflow_validation(two_phase_grains_ranks_1_vs_16 compare two_phase_grains_crosscheck.yaml 2
  "fluid.ranks=1" "fluid.ranks=8 immersed.ranks=4 particles.ranks=4")
coflow_validation(two_phase_grain_interface_60 grain_interface two_phase_grain_interface.yaml 1)
coflow_validation(two_phase_grain_interface_90 grain_interface two_phase_grain_interface.yaml 1
  --set particles.species.grain.contact_angle=90 --set run.end_time=83.333)
coflow_validation(two_phase_grain_interface_120 grain_interface two_phase_grain_interface.yaml 1
  --set particles.species.grain.contact_angle=120)
coflow_validation(two_phase_capillary_bridge bridge two_phase_capillary_bridge.yaml 1)
# The seed's wetting of grains across ranks, and psm grains in one fluid
# beside interior solids (the same core, red alone).
coflow_validation(two_phase_grains_ranks_1_vs_4_seed compare two_phase_grains_crosscheck.yaml 2
  "fluid.ranks=1 fluid.two_phase.wetting=seed" "fluid.ranks=4 fluid.decomposition=[2,2,1] fluid.two_phase.wetting=seed")
coflow_validation(solids_grains_vs_reference compare solids_grains_crosscheck.yaml 1
  "fluid.solver=lbm" "fluid.solver=lbm-reference")
coflow_validation(solids_grains_ranks_1_vs_4 compare solids_grains_crosscheck.yaml 2
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[2,2,1]")
