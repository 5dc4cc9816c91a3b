#pragma once
// The step's buffers (island systems, body-space matrices and their factors) are sized by
// the islands, which change every step, so they are allocated and freed every step. glibc returns
// large freed blocks to the kernel (mmap threshold, heap trimming), and the next step faults every
// page back in, zeroed: on a resting 200-rock pile that was three quarters of the solve. Keeping
// freed memory in the heap makes the next step's allocations reuse it.
namespace rbpart {

// Raises glibc's mmap and trim thresholds for the process, once (later calls do nothing). Called
// by World's constructor and the CLI; an embedding that needs glibc's defaults can restore them with
// mallopt after constructing its World.
void keep_freed_memory();

}  // namespace rbpart
