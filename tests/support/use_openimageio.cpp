// The tests read and write PNG and EXR files as Puff's tools do: the OpenImageIO codec is installed
// before any test runs (gtest_main is the main; this object's initializer runs before it).
#include <puff/io/openimageio.h>

namespace {
const bool kOpenImageIO = (puff::io::useOpenImageIO(), true);
}  // namespace
