#pragma once
// Freed heap memory stays in the process. A decomposed DEM charge's edits serialise, gather, assemble and cut the
// whole charge (tens of MB per buffer, several buffers per edit, every crushing batch); glibc maps each such buffer
// afresh and unmaps it when freed, so every use page-faults its memory in again, which on the virtual machines we run
// on costs more than the copies themselves (measured in src/dem/README.md, "What an edit costs").
namespace core {

// Call first thing in main() of a program that rebuilds large buffers over and over: large allocations come from
// the heap instead of fresh mappings, and up to 1 GiB freed at the heap's top is kept for the next ones. Returns
// false when the C library refused a setting (the program runs on, as before).
bool keep_freed_heap();

}  // namespace core
