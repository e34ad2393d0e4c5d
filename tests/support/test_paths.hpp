#pragma once
// Where the tests find the repository (boards), the shared data (measured recordings) and
// where they keep artefacts. Defined in a source configured into the build directory
// (tests/support/test_paths.cpp.in), so the test sources carry no absolute path and compile
// to identical objects in every clone (ccache hits).
namespace amb::test {

const char* source_dir();    ///< the repository root
const char* shared_dir();    ///< ../shared next to the repository, or next to its local origin (tests/CMakeLists.txt)
const char* artefact_dir();  ///< BUILD/artefacts: files kept for a person to look at

}  // namespace amb::test
