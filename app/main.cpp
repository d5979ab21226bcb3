// millnet command-line entry point: a thin CLI11 dispatcher (subcommands live in app/cmd_*.cpp).
#include <cstdio>
int main() { std::puts("millnet"); return 0; }
