#include "cl/device.h"
#include <cstdio>
int main() {
    for (auto& d : ht::list_devices()) std::printf("%d %s\n", d.index, d.name.c_str());
    return 0;
}
