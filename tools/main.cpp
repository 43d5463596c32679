#include <cstdio>
#include "mbrt/accel.h"
int main() { std::printf("mbrt\n"); return 0; }
