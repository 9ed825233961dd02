#include <cli/app.h>

#include "options.h"

int main(int argc, char** argv) { return puff::cli::main("puffrender", argc, argv, puff::app::parse, puff::app::run); }
