// puffview: main parses and makes one call (docs/style.md, "Apps"); the viewer lives in puffview_lib.
#include <cli/app.h>

#include <puffview/options.h>

int main(int argc, char** argv) { return puff::cli::main("puffview", argc, argv, puff::view::parse, puff::view::run); }
