# The cores a multi-rank test keeps busy is less than its ranks where its
# components wait for each other (a waiting rank sleeps: coupler/src/wait.cpp)
# or where it runs its cases one after another. ctest -j2 runs a test with
# PROCESSORS 2 or more alone; the tests below, measured one at a time (CPU
# seconds over wall seconds, /usr/bin/time around ctest -R, 2-core AMD EPYC
# VM, 2026-12-06) at under 1.5 cores busy and 2 s or more, get PROCESSORS 1,
# so that another test runs beside them. The other 155 of the 213 multi-rank
# tests keep their ranks as PROCESSORS: 119 that take under 2 s, 34 that kept
# 1.5 to 2 cores busy, and the fault, launcher and cluster tests, whose time
# limits are a few seconds.
# Included by tests/CMakeLists.txt after every test is defined; a name that is
# no test is reported. The number after each name is the cores it kept busy.
set(coflow_test_busy_cores
  coupler.discovery_errors 0.29  # 6 ranks, 3.6 s
  coupler.point_crossing 1.37  # 3 ranks, 2.3 s
  output.paraview_reads_amr 0.85  # 2 ranks, 2.3 s
  output.paraview_reads_taylor_green 0.79  # 2 ranks, 3.9 s
  restart.changed_columns 0.94  # 2 ranks, 2.4 s
  restart.damaged_checkpoints 0.52  # 2 ranks, 14.2 s
  restart.dem_bonds_2_ranks 1.03  # 2 ranks, 4.4 s
  restart.dem_mesh_wall_2_ranks 0.75  # 2 ranks, 3.4 s
  restart.dpm_inlet_blocked 0.92  # 3 ranks, 3.9 s
  restart.dpm_jet_2_ranks 1.34  # 4 ranks, 6.3 s
  restart.fv_2_ranks 0.81  # 2 ranks, 3.5 s
  restart.fv_amr_2_ranks 1.44  # 2 ranks, 7.6 s
  restart.fv_amr_k_epsilon_2_ranks 1.11  # 2 ranks, 4.7 s
  restart.fv_amr_other_periodicity_refused 1.35  # 2 ranks, 2.1 s
  restart.fv_k_epsilon_2_ranks 1.44  # 2 ranks, 7.6 s
  restart.fv_k_epsilon_log_law 0.94  # 4 ranks, 8.5 s
  restart.taylor_green 0.65  # 2 ranks, 3.1 s
  restart.two_phase_2_ranks 0.72  # 2 ranks, 3.4 s
  restart.two_phase_fewer_ranks 0.71  # 2 ranks, 3.4 s
  restart.two_phase_grains 1.07  # 3 ranks, 4.7 s
  restart.two_phase_grains_central 1.09  # 3 ranks, 4.7 s
  restart.two_phase_grains_interpolated 1.09  # 3 ranks, 4.8 s
  restart.two_phase_other_ranks 0.60  # 2 ranks, 3.5 s
  validation.dem_reference_restart_from_dem_2_ranks 0.85  # 2 ranks, 2.3 s
  validation.dem_two_sphere_impact_large_box 1.49  # 2 ranks, 2.3 s
  validation.dpm_inlet_stream_ranks_1_vs_3 1.45  # 5 ranks, 3.0 s
  validation.dpm_jet_plate_fv 1.29  # 3 ranks, 6.1 s
  validation.dpm_jet_plate_no_pp 1.18  # 3 ranks, 3.6 s
  validation.dpm_jet_ranks_1_vs_3 1.40  # 5 ranks, 3.7 s
  validation.dpm_ranks_1_vs_4 1.27  # 5 ranks, 2.4 s
  validation.dpm_reference_restart_from_dpm_2_ranks 1.00  # 2 ranks, 23.5 s
  validation.dpm_two_way_fv_ranks_1_vs_16 1.50  # 16 ranks, 2.3 s
  validation.dpm_two_way_fv_vs_lbm 1.39  # 3 ranks, 2.5 s
  validation.dpm_two_way_scattered_layouts 1.47  # 7 ranks, 3.7 s
  validation.fv_amr_ke_intensity_ranks_1_vs_2 1.19  # 2 ranks, 3.7 s
  validation.fv_amr_ke_ranks_1_vs_2 1.20  # 2 ranks, 3.1 s
  validation.fv_amr_ke_table_ranks_1_vs_2 1.14  # 2 ranks, 2.8 s
  validation.fv_amr_vortex_implicit_ranks 1.20  # 2 ranks, 4.0 s
  validation.fv_amr_vortex_ranks 1.23  # 2 ranks, 3.5 s
  validation.fv_ke_log_law_ranks_1_vs_4 1.40  # 4 ranks, 2.8 s
  validation.fv_ke_ranks_1_vs_2_channel 1.31  # 2 ranks, 6.1 s
  validation.fv_ranks_1_vs_2_taylor_green 1.07  # 2 ranks, 2.1 s
  validation.fv_taylor_green_order_space 0.68  # 2 ranks, 2.0 s
  validation.ibm_ranks_1_vs_2_fixed 1.35  # 4 ranks, 3.9 s
  validation.ibm_ranks_1_vs_2_in_predictor 1.32  # 4 ranks, 3.6 s
  validation.ibm_ranks_1_vs_2_moving 1.35  # 4 ranks, 3.6 s
  validation.ibm_with_particles_ranks_1_vs_2 1.36  # 6 ranks, 2.2 s
  validation.lbm_ranks_1_vs_4_duct_inlet 1.22  # 4 ranks, 3.7 s
  validation.lbm_vs_reference_duct_inlet 0.96  # 2 ranks, 12.4 s
  validation.lbm_vs_reference_z_inlet 0.80  # 2 ranks, 2.1 s
  validation.psm_rotating_sphere 1.44  # 3 ranks, 4.9 s
  validation.solids_grains_ranks_1_vs_4 1.34  # 6 ranks, 2.2 s
  validation.solids_sphere_array_tau_central 0.97  # 2 ranks, 15.9 s
  validation.two_phase_grains_central_vs_reference 1.11  # 3 ranks, 4.7 s
  validation.two_phase_grains_interpolated_ranks_1_vs_4 1.37  # 6 ranks, 2.1 s
  validation.two_phase_grains_interpolated_vs_reference 1.12  # 3 ranks, 5.1 s
  validation.two_phase_grains_ranks_1_vs_4 1.38  # 6 ranks, 2.1 s
  validation.two_phase_grains_vs_reference_seed_phase 1.14  # 3 ranks, 4.0 s
)
list(LENGTH coflow_test_busy_cores n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 2)
  list(GET coflow_test_busy_cores ${i} t)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES PROCESSORS 1)
  else()
    message(WARNING "tests/test_processors.cmake: no test named ${t}")
  endif()
endforeach()
