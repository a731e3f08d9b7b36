// concurrent_pipelines_bench: how many frames a second one process renders with one pipeline
// against two pipelines on two threads (each its own GL context on the process' one EGL
// display), the same configuration replayed (as `lumar bench --replay`). On a software
// rasteriser one pipeline leaves cores idle while its passes wait for each other; the second
// pipeline's frames show how much of that a second context in flight could fill (issue 18:
// the ceiling for rendering a frame's environment maps on a context of their own while the
// previous frame is shaded).
//
//   concurrent_pipelines_bench CONFIG [FRAMES] [ROUNDS]
//
// Prints, per round, frames per second alone and together (the sum of both pipelines').
//
// car.toml with bloom on llvmpipe 22.3, 2 cores (2026-12-05): together 32.7-33.5 fps against
// 27.7-31.2 alone, +6 to +21 % in 3 rounds. Two `lumar bench --replay` processes side by side
// made 38.9-42.7 fps together against 30.5-32.8 for one alone (+19 to +40 %, each ~50 ms of
// CPU a frame either way): a process' contexts share one llvmpipe screen, whose rasteriser
// takes their scenes from one queue, so most of the idle is out of a second context's reach.
// With the second pipeline on another EGL display (for the measurement, EglDisplay::
// surfaceless() changed to hand a second caller device(0), Mesa's software device, instead of
// the shared surfaceless display) the two made 39.8-42.6 fps together against 27.9-31.2 alone
// (+33 to +46 %): each display is a screen of its own, with a rasteriser of its own. GL objects
// cannot be shared between displays, so a renderer built on that would hand its environment
// maps from one to the other through memory.
//
// That renderer was built and measured (2026-12-05, not landed): the maps of frame N drawn on
// Mesa's software EGL device by a thread of their own while frame N was shaded with frame
// N-1's, handed over as texels (readback ~0.9 ms, upload ~0.6 ms a frame). car.toml with bloom,
// replayed, 4 interleaved pairs: 34.2/33.9/32.8/33.1 fps against 33.0/32.2/32.2/35.5 alone
// (+3 % by the medians), CPU per frame +1 ms (the shadow map drawn on both displays), peak
// resident memory 123 -> 169 MiB (a second llvmpipe screen, the models twice). Its frames waited
// 1.7 ms a frame for the maps; the shading itself slowed from ~21 to ~26 ms beside them. One
// pipeline alone keeps the two cores ~80-85 % busy (~50 ms of CPU a frame at ~32 fps), so the
// maps moved beside the shading had that idle share to fill, and filled about a fifth of it.
// Full use of the cores would be ~1.2x one pipeline's frames; the +33 to +46 % above exceeds
// that, so part of it is this machine's drift between the rounds alone and together.
#include <barrier>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "app/pipeline.h"
#include "config/config.h"

namespace {

// Frames a second of `frames` steps of `pipeline`.
double run(lumar::Pipeline& pipeline, long frames)
{
    lumar::FrameReport report;
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < frames; ++i)
        if (!pipeline.step(report))
            throw std::runtime_error("the camera source ended");
    return double(frames) / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: concurrent_pipelines_bench CONFIG [FRAMES] [ROUNDS]\n");
        return 2;
    }
    try {
        const lumar::Config config = lumar::loadConfig(argv[1]);
        const long frames = argc > 2 ? std::atol(argv[2]) : 200;
        const int rounds = argc > 3 ? std::atoi(argv[3]) : 3;
        constexpr int kReplayFrames = 4;
        lumar::Pipeline first(config, false, nullptr, kReplayFrames);
        first.detectInBackground();
        run(first, 10); // warm-up: programs linked, maps built
        // The second pipeline lives on a thread of its own, made, stepped and destroyed there
        // (its context is current on that thread), in step with this one: a round's second
        // half runs both. Both threads pass every barrier whatever fails (the other would wait
        // at it for ever); a failure stops the runs and is rethrown once both are done.
        std::barrier sync(2);
        std::vector<double> together(size_t(rounds), 0.0);
        std::exception_ptr failure, otherFailure; // each written by its own thread alone
        const auto attempt = [](std::exception_ptr& failed, const auto& work) {
            if (failed)
                return;
            try {
                work();
            } catch (...) {
                failed = std::current_exception();
            }
        };
        std::thread other([&] {
            std::optional<lumar::Pipeline> second;
            attempt(otherFailure, [&] {
                second.emplace(config, false, nullptr, kReplayFrames);
                second->detectInBackground();
                run(*second, 10);
            });
            sync.arrive_and_wait(); // both warmed up
            for (int round = 0; round < rounds; ++round) {
                sync.arrive_and_wait(); // `first` alone is done
                attempt(otherFailure, [&] { together[size_t(round)] = run(*second, frames); });
                sync.arrive_and_wait();
            }
        });
        sync.arrive_and_wait();
        for (int round = 0; round < rounds; ++round) {
            double alone = 0.0, a = 0.0;
            attempt(failure, [&] { alone = run(first, frames); });
            sync.arrive_and_wait();
            attempt(failure, [&] { a = run(first, frames); });
            sync.arrive_and_wait(); // `together` and `otherFailure` written before it
            if (failure || otherFailure)
                continue;
            const double b = together[size_t(round)];
            std::printf("round %d: alone %.2f fps, together %.2f + %.2f = %.2f fps (%+.0f %%)\n", round + 1, alone, a,
                        b, a + b, 100.0 * ((a + b) / alone - 1.0));
            std::fflush(stdout);
        }
        other.join();
        if (failure)
            std::rethrow_exception(failure);
        if (otherFailure)
            std::rethrow_exception(otherFailure);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "concurrent_pipelines_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
