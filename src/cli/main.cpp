#include "cli/app.h"

int main(int argc, char** argv) { return gyrosid::cli::main(argc, argv); }
