#include "core/helper_thread.h"

namespace lumar {

HelperThread::HelperThread() : thread_([this] { run(); }) {}

HelperThread::~HelperThread()
{
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

void HelperThread::run()
{
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stopping_ || (job_ && !finished_); });
        if (stopping_)
            return;
        const std::function<void()>* job = job_;
        lock.unlock();
        std::exception_ptr error;
        try {
            (*job)();
        } catch (...) {
            error = std::current_exception();
        }
        lock.lock();
        error_ = error;
        finished_ = true;
        done_.notify_one();
    }
}

void HelperThread::runAlongside(const std::function<void()>& theirs, const std::function<void()>& ours)
{
    {
        const std::lock_guard lock(mutex_);
        job_ = &theirs;
        finished_ = false;
        error_ = nullptr;
    }
    wake_.notify_one();
    std::exception_ptr ourError;
    try {
        ours();
    } catch (...) {
        ourError = std::current_exception();
    }
    std::exception_ptr theirError;
    {
        std::unique_lock lock(mutex_);
        done_.wait(lock, [this] { return finished_; });
        job_ = nullptr;
        theirError = error_;
    }
    if (ourError)
        std::rethrow_exception(ourError);
    if (theirError)
        std::rethrow_exception(theirError);
}

} // namespace lumar
