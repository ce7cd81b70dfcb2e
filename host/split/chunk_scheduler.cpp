#include "split/chunk_scheduler.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

namespace ht {

std::vector<DeviceShare> render_chunks(const std::vector<Renderer*>& devices, const std::vector<std::string>& names,
                                       SampleAccumulator& acc, const std::vector<int>& chunks,
                                       const ChunkRunHooks& hooks) {
    const ChunkGrid grid = acc.grid();
    Film zero;
    zero.width = acc.width();
    zero.height = acc.height();
    zero.rgba.assign(4 * size_t(zero.width) * size_t(zero.height), 0.0f);

    // The work queue, in chunk order: lower chunks first keeps the prefix fold moving and
    // bounds how many finished-but-unfoldable chunks wait in memory.
    std::deque<FilmSegment> queue;
    for (int j : chunks) {
        if (acc.unfinished(j)) queue.push_back(acc.take_unfinished(j));
        else queue.push_back(FilmSegment{grid.begin(j), 0, Film{}});
    }

    std::mutex m;
    std::condition_variable cv;
    std::vector<FilmSegment> finished;  // handed from the device threads to this one
    std::atomic<bool> stop{false};
    std::atomic<int> samples{0};
    std::exception_ptr failure;
    std::vector<DeviceShare> shares(devices.size());
    int running = int(devices.size());

    auto worker = [&](size_t d) {
        Renderer& r = *devices[d];
        DeviceShare& share = shares[d];
        share.name = names[d];
        try {
            for (;;) {
                FilmSegment seg;
                {
                    std::lock_guard<std::mutex> lock(m);
                    if (stop || queue.empty()) break;
                    seg = std::move(queue.front());
                    queue.pop_front();
                }
                const int end = grid.end(grid.chunk_of(seg.first));
                r.upload_film(seg.count > 0 ? seg.film : zero);
                const auto t0 = std::chrono::steady_clock::now();
                int rendered = 0;
                while (seg.first + seg.count < end && !stop) {
                    const int n = std::min(r.samples_per_pass(), end - (seg.first + seg.count));
                    r.render_samples(uint32_t(seg.first + seg.count), uint32_t(n));
                    seg.count += n;
                    rendered += n;
                    samples += n;
                }
                if (rendered > 0) r.download_film(seg.film);
                share.busy_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                share.samples += rendered;
                if (seg.first + seg.count == end) ++share.chunks;
                std::lock_guard<std::mutex> lock(m);
                if (seg.count > 0) finished.push_back(std::move(seg));
                cv.notify_all();
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(m);
            if (!failure) failure = std::current_exception();
            stop = true;
        }
        std::lock_guard<std::mutex> lock(m);
        --running;
        cv.notify_all();
    };

    std::vector<std::thread> threads;
    for (size_t d = 0; d < devices.size(); ++d) threads.emplace_back(worker, d);

    // The calling thread owns acc: it folds finished chunks, reports progress and decides stops.
    // A failure here (a checkpoint that cannot be written) must still stop and join the device
    // threads before it propagates: destroying a joinable std::thread terminates the process.
    std::unique_lock<std::mutex> lock(m);
    try {
        for (;;) {
            cv.wait_for(lock, std::chrono::milliseconds(50));
            std::vector<FilmSegment> done;
            done.swap(finished);
            const bool all_done = running == 0;
            const bool failed = failure != nullptr;
            lock.unlock();
            bool any_complete = false;
            for (auto& s : done) {
                any_complete |= grid.boundary(s.first + s.count);
                acc.add(std::move(s));
            }
            if (hooks.progress) hooks.progress(samples.load());
            if (any_complete && hooks.chunk_finished && !failed) hooks.chunk_finished();
            if (!stop && hooks.should_stop && hooks.should_stop()) stop = true;
            lock.lock();
            if (all_done && finished.empty()) break;
        }
    } catch (...) {
        stop = true;
        if (lock.owns_lock()) lock.unlock();
        for (auto& t : threads) t.join();
        throw;
    }
    lock.unlock();
    for (auto& t : threads) t.join();
    // Chunks never started (a stop) stay pending; unfinished ones were returned above.  Segments
    // taken from acc for continuation but never claimed go back unchanged.
    for (auto& s : queue)
        if (s.count > 0) acc.add(std::move(s));
    if (failure) std::rethrow_exception(failure);
    return shares;
}

}  // namespace ht
