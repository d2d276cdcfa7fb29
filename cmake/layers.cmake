# The floors of pluvia, bottom to top, in one place. src/<name>/ builds pluvia_<name>; cli/ is the
# `pluvia` executable. PLUVIA_LAYER_<name> lists the libraries whose headers the sources of <name>
# may include (`#include "<library>/..."`) besides its own; a floor names only floors below it.
# "pluvia/" (the generated version header) is open to all; tests/ may include anything.
# The ctest test `layers` (cmake/check_layers.cmake) checks every source against this; the build
# itself fails on an include of a library that is not linked (include roots, top CMakeLists.txt).
set(PLUVIA_LAYERS util image io geometry preset sfm optics envmap rain gpu derain pipeline stages
                  lab farm cli)
set(PLUVIA_LAYER_util "")
set(PLUVIA_LAYER_image util)
set(PLUVIA_LAYER_io image util)
set(PLUVIA_LAYER_geometry image util)
set(PLUVIA_LAYER_preset util)
set(PLUVIA_LAYER_sfm geometry io image util)
set(PLUVIA_LAYER_optics geometry io image util)
set(PLUVIA_LAYER_envmap optics geometry io image util)
set(PLUVIA_LAYER_rain optics geometry image util)
set(PLUVIA_LAYER_gpu rain image util)
set(PLUVIA_LAYER_derain rain io image util)
set(PLUVIA_LAYER_pipeline preset optics rain geometry io image util)
set(PLUVIA_LAYER_stages pipeline gpu derain rain envmap optics sfm preset geometry io image util)
# The measurement harness: reports, synthetic inputs, error metrics. Only cli's report and bench
# commands and the tests use it; nothing on the render path does.
set(PLUVIA_LAYER_lab gpu derain rain envmap optics sfm geometry io image util)
# Farm jobs: the scripts a scheduler runs (Slurm), their submission and state, a movie's assembly.
set(PLUVIA_LAYER_farm io image util)
set(PLUVIA_LAYER_cli farm lab stages pipeline gpu derain rain envmap optics sfm preset geometry io
                     image util)
# Headers of gpu/ (the renderer and its GL helpers) are for these files and folders only.
set(PLUVIA_GPU_USERS src/gpu/ src/lab/ src/stages/rain_stage.cpp cli/bench_strokes.cpp
                     cli/rain_backend_variable.cpp
                     cli/bench_lod.cpp)
