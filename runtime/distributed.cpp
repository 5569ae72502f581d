#include "runtime/distributed.h"

#include <algorithm>
#include <cstdlib>
#include <type_traits>

#ifdef PL_WITH_MPI
#include <mpi.h>
#endif

namespace pl {

namespace {
constexpr size_t kChunkPixels = 64;
}

#ifdef PL_WITH_MPI

namespace {
// MPI starts only under a launcher (mpirun, srun): its set-up costs a
// third of a second, which every other run would pay.
bool active = false;
bool launchedByMpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
        if (std::getenv(name)) return true;
    return false;
}
}  // namespace

Distributed::Distributed(int* argc, char*** argv) {
    active = launchedByMpi();
    if (active) MPI_Init(argc, argv);
}
Distributed::~Distributed() {
    if (active) MPI_Finalize();
}
int Distributed::rank() {
    int r = 0;
    if (active) MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}
int Distributed::ranks() {
    int n = 1;
    if (active) MPI_Comm_size(MPI_COMM_WORLD, &n);
    return n;
}
bool Distributed::enabled() { return true; }

void gatherOnRankZero(Film& film, PathStats& stats) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n == 1) return;
    static_assert(std::is_trivially_copyable_v<PathStats>);
    if (me != 0) {
        const std::vector<char> bytes = film.packPixels(pixelsOfRank(film.pixelCount(), me, n));
        MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, 0, 1, MPI_COMM_WORLD);
        MPI_Send(&stats, int(sizeof stats), MPI_BYTE, 0, 2, MPI_COMM_WORLD);
        return;
    }
    // In rank order: the same sums of the statistics every time.
    for (int r = 1; r < n; ++r) {
        const std::vector<uint32_t> pixels = pixelsOfRank(film.pixelCount(), r, n);
        std::vector<char> bytes(pixels.size() * Film::packedBytesPerPixel());
        MPI_Recv(bytes.data(), int(bytes.size()), MPI_BYTE, r, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        film.unpackPixels(pixels, bytes.data());
        PathStats theirs;
        MPI_Recv(&theirs, int(sizeof theirs), MPI_BYTE, r, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        stats += theirs;
    }
}

bool anyRankFailed(bool failed) {
    if (!active) return failed;
    int mine = failed ? 1 : 0, any = 0;
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return any != 0;
}

#else

Distributed::Distributed(int*, char***) {}
Distributed::~Distributed() = default;
int Distributed::rank() { return 0; }
int Distributed::ranks() { return 1; }
bool Distributed::enabled() { return false; }
void gatherOnRankZero(Film&, PathStats&) {}
bool anyRankFailed(bool failed) { return failed; }

#endif

std::vector<uint32_t> pixelsOfRank(size_t pixelCount, int rank, int ranks) {
    std::vector<uint32_t> pixels;
    for (size_t chunk = size_t(rank); chunk * kChunkPixels < pixelCount; chunk += size_t(ranks))
        for (size_t p = chunk * kChunkPixels; p < std::min(pixelCount, (chunk + 1) * kChunkPixels); ++p)
            pixels.push_back(uint32_t(p));
    return pixels;
}

}  // namespace pl
