#include "experiments/cli/commands.h"

int main(int argc, char** argv) { return lb::lightbenchMain(argc, argv); }
