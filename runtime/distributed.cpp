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

std::vector<std::vector<double>> shareBlocksByPixel(std::vector<double> mine, size_t pixelCount, int blocks) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n == 1) return {std::move(mine)};
    std::vector<double> send;
    std::vector<int> sendCounts(size_t(n), 0), sendOffsets(size_t(n), 0);
    for (int q = 0; q < n; ++q) {
        const std::vector<uint32_t> theirs = pixelsOfRank(pixelCount, q, n);
        sendOffsets[size_t(q)] = int(send.size());
        if (me >= blocks) continue;
        for (uint32_t p : theirs) send.push_back(mine[p]);
        sendCounts[size_t(q)] = int(theirs.size());
    }
    const int own = int(pixelsOfRank(pixelCount, me, n).size());
    std::vector<double> received(size_t(own) * size_t(blocks));
    std::vector<int> receiveCounts(size_t(n), 0), receiveOffsets(size_t(n), 0);
    for (int r = 0; r < blocks; ++r) {
        receiveCounts[size_t(r)] = own;
        receiveOffsets[size_t(r)] = r * own;
    }
    MPI_Alltoallv(send.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE, received.data(),
                  receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE, MPI_COMM_WORLD);
    std::vector<std::vector<double>> out(static_cast<size_t>(blocks));
    for (int r = 0; r < blocks; ++r)
        out[size_t(r)].assign(received.begin() + long(r) * own, received.begin() + long(r + 1) * own);
    return out;
}

std::vector<std::string> gatherTextOnRankZero(const std::string& mine) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n == 1) return {mine};
    if (me != 0) {
        const uint64_t size = mine.size();
        MPI_Send(&size, 1, MPI_UINT64_T, 0, 3, MPI_COMM_WORLD);
        MPI_Send(mine.data(), int(size), MPI_CHAR, 0, 4, MPI_COMM_WORLD);
        return {};
    }
    std::vector<std::string> all{mine};
    for (int r = 1; r < n; ++r) {
        uint64_t size = 0;
        MPI_Recv(&size, 1, MPI_UINT64_T, r, 3, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        std::string text(size, '\0');
        MPI_Recv(text.data(), int(size), MPI_CHAR, r, 4, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        all.push_back(std::move(text));
    }
    return all;
}

uint32_t broadcastFromRankZero(uint32_t value) {
    if (active) MPI_Bcast(&value, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    return value;
}

void broadcastFromRankZero(Film& film, PathStats& stats) {
    if (!active || Distributed::ranks() == 1) return;
    std::vector<uint32_t> all(film.pixelCount());
    for (size_t p = 0; p < all.size(); ++p) all[p] = uint32_t(p);
    std::vector<char> bytes = Distributed::rank() == 0 ? film.packPixels(all)
                                                       : std::vector<char>(all.size() * Film::packedBytesPerPixel());
    // In pieces: MPI counts are ints.
    constexpr size_t kPiece = size_t(1) << 30;
    for (size_t offset = 0; offset < bytes.size(); offset += kPiece)
        MPI_Bcast(bytes.data() + offset, int(std::min(kPiece, bytes.size() - offset)), MPI_BYTE, 0, MPI_COMM_WORLD);
    if (Distributed::rank() != 0) film.unpackPixels(all, bytes.data());
    MPI_Bcast(&stats, int(sizeof stats), MPI_BYTE, 0, MPI_COMM_WORLD);
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
std::vector<std::vector<double>> shareBlocksByPixel(std::vector<double> mine, size_t, int) { return {std::move(mine)}; }
std::vector<std::string> gatherTextOnRankZero(const std::string& mine) { return {mine}; }
uint32_t broadcastFromRankZero(uint32_t value) { return value; }
void broadcastFromRankZero(Film&, PathStats&) {}
bool anyRankFailed(bool failed) { return failed; }

#endif

std::vector<uint32_t> pixelsOfRank(size_t pixelCount, int rank, int ranks) {
    std::vector<uint32_t> pixels;
    for (size_t chunk = size_t(rank); chunk * kChunkPixels < pixelCount; chunk += size_t(ranks))
        for (size_t p = chunk * kChunkPixels; p < std::min(pixelCount, (chunk + 1) * kChunkPixels); ++p)
            pixels.push_back(uint32_t(p));
    return pixels;
}

int rankOfPixel(uint32_t pixel, int ranks) { return int(size_t(pixel) / kChunkPixels % size_t(ranks)); }

size_t positionInShare(uint32_t pixel, int ranks) {
    return (size_t(pixel) / kChunkPixels / size_t(ranks)) * kChunkPixels + size_t(pixel) % kChunkPixels;
}

}  // namespace pl
