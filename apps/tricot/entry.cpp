// The `tricot` program's entry point: everything is in tricot_cli_main (main.cpp), which tests also run.
#include "verbs.hpp"

int main(int argc, char** argv) { return tricot_cli_main(argc, argv); }
