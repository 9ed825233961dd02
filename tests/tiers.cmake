# The test tiers: every file in tests/unit/ is in exactly one, and builds into puff_tests_TIER, whose
# tests carry the ctest label TIER (docs/testing.md, "Tiers"):
#   unit  no GL context, no tool: the simulator, scenes, meshes, colour, metrics, files (under a minute)
#   gl    draws with GL in-process (OSMesa), no tool run
#   e2e   runs the tools (puffbake, puffrender, puffview), the art scenes' goldens, the install
#   slow  the tumbling sweeps: thousands of poses, sampled here and swept whole by tests/bench/report.sh
set(PUFF_TEST_TIERS unit gl e2e slow)

set(PUFF_TESTS_UNIT
  before_init_gl_test.cpp blackbody_test.cpp bodies_test.cpp cel_popping_test.cpp detail_video_test.cpp files_test.cpp
  flipbook_sheet_test.cpp
  frame_evaluator_test.cpp fuzz_regressions_test.cpp golden_test.cpp image_limits_test.cpp label_test.cpp
  life_curves_test.cpp media_coverage_test.cpp media_physical_test.cpp mesh_gltf_test.cpp mesh_io_test.cpp mesh_test.cpp metrics_test.cpp progress_test.cpp render_path_test.cpp
  scene_roundtrip_test.cpp
  scene_evaluate_test.cpp scene_file_edit_test.cpp scene_loop_test.cpp scene_test.cpp
  sim_forces_test.cpp sim_loop_test.cpp sim_test.cpp sim_threads_test.cpp)
set(PUFF_TESTS_GL
  bake_atlas_test.cpp bake_lod_mips_test.cpp fixedfunc_draw_test.cpp host_layers_errors_test.cpp
  host_state_bindings_test.cpp hull_occluders_test.cpp media_layers_test.cpp media_model_test.cpp nailboard_shadow_test.cpp reference_gpu_test.cpp
  bake_test.cpp cel_floor_test.cpp cel_reference_test.cpp colour_pipeline_test.cpp compose_test.cpp debug_names_test.cpp
  cooked_image_test.cpp fixedfunc_test.cpp gl_context_test.cpp host_depth_test.cpp host_media_test.cpp
  host_state_test.cpp host_targets_test.cpp lod_kept_test.cpp media_cartoon_test.cpp media_popping_test.cpp media_sort_test.cpp
  media_test.cpp nailboard_once_test.cpp nailboard_test.cpp opaque_test.cpp opaque_volume_test.cpp reference_test.cpp reload_test.cpp
  render_test.cpp shader_test.cpp shadow_methods_test.cpp shadow_receivers_test.cpp stability_inputs_test.cpp stability_test.cpp
  steady_test.cpp)
set(PUFF_TESTS_E2E
  budget_cel_test.cpp hull_occluders_scene_test.cpp lit_once_scene_test.cpp puffrender_flipbook_test.cpp puffrender_loop_test.cpp puffrender_maps_test.cpp puffrender_motion_test.cpp
  puffrender_paths_test.cpp
  bake_replace_test.cpp budget_test.cpp colour_test.cpp gl_failures_test.cpp gpubench_test.cpp media_coverage_scene_test.cpp media_scene_test.cpp parity_test.cpp
  puffbake_cli_test.cpp puffbake_gltf_test.cpp puffrender_cli_test.cpp puffview_keep_test.cpp puffview_soak_test.cpp puffview_test.cpp puffview_window_test.cpp scene_golden_test.cpp)
set(PUFF_TESTS_SLOW
  tumble_test.cpp tumble_split_test.cpp)

# Suites the sanitized run (.ci/run) leaves out, which also carry the label `unsanitized`
# (docs/testing.md, "Sanitizers"): two sweep one method over many light directions, each point the
# same code with other numbers; two compare shadows and silhouettes with the cel reference on
# lumpy, long and cluster puffs baked in-process, code the receivers' suites
# (AllMethods/ShadowReceivers, MapAndReference/ObjectShadows, Reference/ObjectReceivers,
# CelMethods/ObjectReceivers) run under the sanitizers too. Reload remakes a renderer 34 times from
# files, its sanitized time (91 s) the sanitizer's allocator under the image reads, which the fuzz
# harnesses run sanitized (atlas sidecar, every map, detail clips).
set(PUFF_UNSANITIZED_SUITES CelMethods/ShadowOfASphere Reference/ShadowOfASphere ShadowMethods CelReference Reload)

# A test file in no tier, or in two, is an error here rather than a test that never runs.
file(GLOB _puff_test_files RELATIVE ${CMAKE_CURRENT_LIST_DIR}/unit CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/unit/*.cpp)
set(_puff_tiered ${PUFF_TESTS_UNIT} ${PUFF_TESTS_GL} ${PUFF_TESTS_E2E} ${PUFF_TESTS_SLOW})
foreach(_f IN LISTS _puff_test_files)
  list(FIND _puff_tiered ${_f} _i)
  if(_i EQUAL -1)
    message(FATAL_ERROR "tests/unit/${_f} is in no test tier: add it to one list in tests/tiers.cmake")
  endif()
  list(REMOVE_AT _puff_tiered ${_i})
  list(FIND _puff_tiered ${_f} _i)
  if(NOT _i EQUAL -1)
    message(FATAL_ERROR "tests/unit/${_f} is in two test tiers in tests/tiers.cmake")
  endif()
endforeach()
foreach(_f IN LISTS _puff_tiered)
  message(FATAL_ERROR "tests/tiers.cmake lists ${_f}, which is not in tests/unit/")
endforeach()
