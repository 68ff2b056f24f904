// SPDX-License-Identifier: Apache-2.0
// Under ASan (make asan): PCL 1.13's HDLGrabber never frees its pcap handle, compiled filter and
// last queued packet when its reading thread ends (libpcl_io, not Mirage); those leaks are
// suppressed for this binary only. Full malloc stacks, so the suppression matches the PCL frame
// under libpcap's own (frame-pointer-less) ones. Without a sanitizer these hooks are never called.
extern "C" const char* __asan_default_options() { return "fast_unwind_on_malloc=0"; }

extern "C" const char* __lsan_default_suppressions() {
    return "leak:pcl::HDLGrabber::readPacketsFromPcap\n"
           "leak:pcl::HDLGrabber::enqueueHDLPacket\n";
}
