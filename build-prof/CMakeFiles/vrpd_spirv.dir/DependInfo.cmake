
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "" "spirv/commit_cells.h" "custom" "spirv/commit_cells.h.d"
  "" "spirv/count_darts.h" "custom" "spirv/count_darts.h.d"
  "" "spirv/emit_samples.h" "custom" "spirv/emit_samples.h.d"
  "" "spirv/init_cells.h" "custom" "spirv/init_cells.h.d"
  "" "spirv/refine_cells.h" "custom" "spirv/refine_cells.h.d"
  "" "spirv/resolve_darts.h" "custom" "spirv/resolve_darts.h.d"
  "" "spirv/scan_add.h" "custom" "spirv/scan_add.h.d"
  "" "spirv/scan_blocks.h" "custom" "spirv/scan_blocks.h.d"
  "" "spirv/scan_sums.h" "custom" "spirv/scan_sums.h.d"
  "" "spirv/scatter_cells.h" "custom" "spirv/scatter_cells.h.d"
  "" "spirv/throw_darts.h" "custom" "spirv/throw_darts.h.d"
  "" "spirv/work_args.h" "custom" "spirv/work_args.h.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
