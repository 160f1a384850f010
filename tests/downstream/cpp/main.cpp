// A downstream C++ program, built against an installed rodkit by CMake
// (find_package(rodkit), rodkit::rodkit_static: the archive and the system
// libraries it needs, derived at rodkit's build). It makes a rod (a
// Kirchhoff rod 2.5 long, 10 elements of Gauss(2)) and checks its mesh against
// i·L/N and its state's length, 13 values per node and stage point:
// 13·(1 + 2)·10 + 13 = 403.
#include <rodkit.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

int main() {
    RodkitRodSpec spec;
    rodkit_rod_spec_default(&spec);
    spec.length = 2.5;
    spec.kirchhoff = 1;  // inextensible, unshearable: bending and twist only
    spec.bending1 = spec.bending2 = 1.0;
    spec.twist = 0.8;
    spec.elements = 10;
    spec.stages = 2;
    RodkitRod *raw = nullptr;
    if (rodkit_rod_new(&spec, &raw) != 0) {
        std::fprintf(stderr, "rodkit_rod_new: %s\n", rodkit_last_error_message());
        return 1;
    }
    std::unique_ptr<RodkitRod, decltype(&rodkit_rod_free)> rod(raw, &rodkit_rod_free);
    int64_t count = 0, unknowns = 0;
    rodkit_rod_node_positions(rod.get(), nullptr, 0, &count);
    std::vector<double> s(static_cast<size_t>(count));
    if (count != 11 || rodkit_rod_node_positions(rod.get(), s.data(), count, &count) != 0) return 1;
    double worst = 0.0;
    for (int64_t i = 0; i <= 10; ++i) worst = std::fmax(worst, std::fabs(s[i] - 0.25 * static_cast<double>(i)));
    rodkit_rod_unknowns(rod.get(), &unknowns);
    std::printf("rodkit %s: rod of 10 elements of Gauss(2), nodes at i L/N to %.1e, %lld unknowns (403)\n",
                RODKIT_VERSION_STRING, worst, static_cast<long long>(unknowns));
    return worst <= 1e-15 && unknowns == 403 ? 0 : 1;
}
