//! Stack high-water mark by painting.
//!
//! At reset, everything between the end of `.bss` (`_stack_end`, where
//! cortex-m-rt puts the stack's far end) and the current stack pointer is
//! filled with a pattern; after the run, the lowest word that no longer holds
//! it is the deepest the stack has been. The stack grows down from
//! `_stack_start` (the top of RAM).

use core::arch::asm;
use core::ptr::{read_volatile, write_volatile};

const PAINT: u32 = 0xC0DE_5AFE;

unsafe extern "C" {
    /// The top of the stack (cortex-m-rt's `link.x`).
    static _stack_start: u32;
    /// The far end of the stack: the end of `.bss`.
    static _stack_end: u32;
}

/// The current stack pointer.
#[inline(always)]
pub fn sp() -> usize {
    let sp: usize;
    // SAFETY: reads a register, touches no memory.
    unsafe { asm!("mov {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags)) };
    sp
}

/// The top of the stack, where it starts.
pub fn top() -> usize {
    &raw const _stack_start as usize
}

fn bottom() -> usize {
    &raw const _stack_end as usize
}

/// Paints the free stack below the current stack pointer, leaving 64 bytes
/// for this leaf function's own use.
#[inline(never)]
pub fn paint() {
    let end = sp().saturating_sub(64) & !3;
    let mut p = bottom();
    while p < end {
        // SAFETY: `[_stack_end, sp - 64)` is RAM that nothing uses yet: below
        // every live frame and above every static.
        unsafe { write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
}

/// The lowest address the stack has reached since [`paint`].
pub fn lowest() -> usize {
    let end = top();
    let mut p = bottom();
    // SAFETY: reads RAM between the end of `.bss` and the top of the stack.
    while p < end && unsafe { read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    p
}
