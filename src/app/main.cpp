// multiray: render frames split across several devices, and measure how well the load
// balancers keep them finishing together. A thin shell over the library (app/cli.h).
#include "app/cli.h"

int main(int argc, char** argv) { return multiray::app::run_cli(argc, argv); }
