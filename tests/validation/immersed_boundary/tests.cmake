# Immersed boundaries by direct forcing (issue 23, seed 003 §4.2.1), on fv:
# the steady cylinder at Re 20 on two grids (D = 8 and 12 cells), extrapolated
# to h -> 0, against the published drag and recirculation length; the seed's repeated direct forcing (mdf) leaves a slip below 1e-3 U;
# a cylinder crossing fluid at rest against a fixed one in a stream (the same
# flow in two frames); 1 rank against 2 for a fixed body cut through by the
# blocks and a moving one (fluid and immersed ranks both).
coflow_validation(ibm_cylinder_re20 pair ibm_cylinder_re20.yaml 1 ibm_extrapolated
  "domain.cells=[216,240,1]" "domain.cells=[324,360,1]")
coflow_validation(ibm_cylinder_mdf_slip ibm_steady ibm_cylinder_fixed_frame.yaml 1
  --set immersed.ibm.iteration=mdf --set immersed.ibm.max_iterations=20)
coflow_validation(ibm_cylinder_frames pair ibm_cylinder_translating.yaml 1 ibm_frames "" "config=ibm_cylinder_fixed_frame.yaml")
set(ibm_short "run.end_time=4.0 run.output.every=4.0")
coflow_validation(ibm_ranks_1_vs_2_fixed compare ibm_cylinder_fixed_frame.yaml 2
  "fluid.ranks=1 ${ibm_short}" "fluid.ranks=2 immersed.ranks=2 fluid.decomposition=[2,1,1] ${ibm_short}")
coflow_validation(ibm_ranks_1_vs_2_moving compare ibm_cylinder_translating.yaml 2
  "fluid.ranks=1 ${ibm_short}" "fluid.ranks=2 immersed.ranks=2 fluid.decomposition=[1,2,1] ${ibm_short}")
