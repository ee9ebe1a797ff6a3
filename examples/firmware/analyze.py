#!/usr/bin/env python3
"""Static audit of the firmware ELF: what the control step can call, how deep
its stack can go, how much code it takes, and every panic path left in it.

    python3 analyze.py ELF [--root parasils_control_step] [--known known-panics.txt]

From `llvm-objdump -d` it builds the call graph (direct calls and tail calls;
an indirect call anywhere below the root is an error, since its target is
unknown) and, for every function, the stack its prologue reserves (`push`,
`vpush`, `sub sp`): the sum of all such instructions, an upper bound. The
stack bound of the root is its frame plus the deepest chain of callees; a
cycle (recursion) below the root makes it unbounded, which is an error.
Exception entry (32 or 104 bytes per active interrupt on a Cortex-M4F) is
not included: the control step takes no interrupt.

A panic site is a call into the panic machinery (`core::panicking::*`,
`unwrap_failed`, slice-index failures, the panic handler). With the firmware's
default panic handler a panic site cannot exist (the link fails); with
`--features panic-report` they can, and this audit lists each one with its
inlined source chain (`llvm-symbolizer`). Sites whose chain mentions an entry
of the known list are reported as known; any other site is an error.

Also an error: any allocator symbol (the firmware has no heap).
Exit status 0 when there is no error.
"""

import argparse
import bisect
import re
import subprocess
import sys

PANIC_NAME = re.compile(
    r"^(core::panicking::|core::option::(unwrap|expect)_failed|core::result::unwrap_failed"
    r"|core::slice::index::|core::str::slice_error_fail|core::panic::|core::cell::panic_"
    r"|__rustc::rust_begin_unwind|rust_begin_unwind)"
)
ALLOC_NAME = re.compile(r"__rust_alloc|__rust_dealloc|__rust_realloc|__rg_alloc|__rdl_alloc|alloc::alloc::")
FUNC = re.compile(r"^([0-9a-f]+) <(.+)>:$")
INSN = re.compile(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$")
TARGET = re.compile(r"^(?:0x)?([0-9a-f]+) <")
BRANCH = re.compile(r"^(bl|blx|b|cbz|cbnz)(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?(\.w|\.n)?$")
REGLIST = re.compile(r"\{([^}]*)\}")


def reg_count(text):
    """Registers in a `{r4-r7, lr}` or `{d8, d9}` list."""
    m = REGLIST.search(text)
    if not m:
        return 0, ""
    n, kind = 0, ""
    for part in m.group(1).split(","):
        part = part.strip()
        if not part:
            continue
        kind = part[0]
        if "-" in part:
            lo, hi = part.split("-")
            n += int(hi.strip()[1:]) - int(lo.strip()[1:]) + 1
        else:
            n += 1
    return n, kind


def imm(text):
    m = re.search(r"#(-?(?:0x[0-9a-f]+|\d+))", text)
    return int(m.group(1), 0) if m else None


def disassemble(elf):
    out = subprocess.run(
        ["llvm-objdump", "-d", "--no-show-raw-insn", "-C", elf],
        check=True, capture_output=True, text=True,
    ).stdout
    funcs = {}  # start -> dict
    cur = None
    for line in out.splitlines():
        m = FUNC.match(line)
        if m:
            name = m.group(2)
            if name.startswith("$"):  # mapping symbol ($t code, $d data) inside a function
                continue
            start = int(m.group(1), 16)
            cur = {"name": name, "start": start, "insns": []}
            funcs[start] = cur
            continue
        m = INSN.match(line)
        if m and cur is not None:
            cur["insns"].append((int(m.group(1), 16), m.group(2), m.group(3)))
    return funcs


def sizes(elf):
    out = subprocess.run(
        ["llvm-nm", "-S", "--defined-only", elf], check=True, capture_output=True, text=True
    ).stdout
    size = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 4 and parts[2].lower() == "t":
            size[int(parts[0], 16) & ~1] = int(parts[1], 16)
    return size


def analyse(funcs):
    starts = sorted(funcs)

    def owner(addr):
        i = bisect.bisect_right(starts, addr) - 1
        return starts[i] if i >= 0 else None

    for f in funcs.values():
        f["calls"] = {}  # callee start -> first call-site address
        f["sites"] = []  # every (call-site address, callee start)
        f["indirect"] = []
        frame, last_mov = 0, {}
        for addr, mnem, ops in f["insns"]:
            base = mnem.split(".")[0]
            m = BRANCH.match(mnem)
            if m and m.group(1) in ("blx",) and not ops.startswith("0x"):
                f["indirect"].append(addr)
            elif base == "bx" and ops.strip() != "lr":
                f["indirect"].append(addr)
            elif m:
                t = TARGET.match(ops.split(",")[-1].strip())
                if t:
                    target = int(t.group(1), 16)
                    callee = owner(target)
                    is_call = m.group(1) in ("bl", "blx")
                    if callee is not None and (callee != f["start"] or (is_call and target == callee)):
                        f["calls"].setdefault(callee, addr)
                        f["sites"].append((addr, callee))
            # Stack reserved by this function.
            if base in ("push", "stmdb") and (base == "push" or ops.startswith("sp!")):
                n, _ = reg_count(ops)
                frame += 4 * n
            elif base == "vpush":
                n, kind = reg_count(ops)
                frame += (8 if kind == "d" else 4) * n
            elif base in ("sub", "subw") and re.match(r"^sp,\s*(sp,\s*)?#", ops):
                frame += imm(ops) or 0
            elif base in ("sub",) and re.match(r"^sp,\s*(sp,\s*)?r\d+$", ops):
                reg = ops.split(",")[-1].strip()
                frame += last_mov.get(reg, 1 << 30)  # unknown: flagged as huge
            elif base in ("str", "strd", "vstr") and re.search(r"\[sp,\s*#-\d+\]!", ops):
                frame -= imm(ops.split("[", 1)[1]) or 0
            if base in ("movw", "mov") and imm(ops) is not None:
                last_mov[ops.split(",")[0].strip()] = imm(ops)
            elif base == "movt" and imm(ops) is not None:
                reg = ops.split(",")[0].strip()
                last_mov[reg] = last_mov.get(reg, 0) + (imm(ops) << 16)
        f["frame"] = frame
    return owner


def reachable(funcs, root):
    """Functions reachable from root, not counting the panic machinery (its
    call sites are the panic sites, reported on their own)."""
    seen, todo = set(), [root]
    while todo:
        s = todo.pop()
        if s in seen or PANIC_NAME.match(funcs[s]["name"]):
            continue
        seen.add(s)
        todo.extend(funcs[s]["calls"])
    return seen


def stack_bound(funcs, root):
    """Deepest stack from root; None on recursion."""
    memo, onpath = {}, set()

    def go(s):
        if s in memo:
            return memo[s]
        if s in onpath:
            raise RecursionError(funcs[s]["name"])
        onpath.add(s)
        deepest = 0
        for c in funcs[s]["calls"]:
            if not PANIC_NAME.match(funcs[c]["name"]):
                deepest = max(deepest, go(c))
        onpath.discard(s)
        memo[s] = funcs[s]["frame"] + deepest
        return memo[s]

    sys.setrecursionlimit(100000)
    return go(root)


def symbolize(elf, addrs):
    if not addrs:
        return {}
    out = subprocess.run(
        ["llvm-symbolizer", "-e", elf, "-i", "-f", "-C"] + ["0x%x" % a for a in addrs],
        check=True, capture_output=True, text=True,
    ).stdout
    chains, blocks = {}, out.strip("\n").split("\n\n")
    for a, block in zip(addrs, blocks):
        lines = block.splitlines()
        frames = []
        for i in range(0, len(lines) - 1, 2):
            fn, loc = lines[i], lines[i + 1]
            loc = re.sub(r"^.*/registry/src/[^/]+/", "", loc)
            loc = re.sub(r"^/rustc/[0-9a-f]+/library/", "", loc)
            loc = re.sub(r"^.*/crates/", "crates/", loc)
            frames.append((fn, loc))
        chains[a] = frames
    return chains


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("elf")
    ap.add_argument("--root", default="parasils_control_step")
    ap.add_argument("--known", default=None)
    args = ap.parse_args()

    known = []
    if args.known:
        for line in open(args.known):
            line = line.split("#", 1)[0].strip()
            if line:
                known.append(line)

    funcs = disassemble(args.elf)
    size = sizes(args.elf)
    analyse(funcs)
    by_name = {f["name"]: s for s, f in funcs.items()}
    if args.root not in by_name:
        print("audit: root function %s not found" % args.root)
        return 1
    root = by_name[args.root]
    errors = 0

    allocs = sorted({f["name"] for f in funcs.values() if ALLOC_NAME.search(f["name"])})
    if allocs:
        errors += 1
        print("audit: ERROR allocator symbols present: " + ", ".join(allocs))

    below = reachable(funcs, root)
    code = sum(size.get(s, 0) for s in below)
    indirect = [(funcs[s]["name"], a) for s in below for a in funcs[s]["indirect"]]
    for name, a in indirect:
        errors += 1
        print("audit: ERROR indirect call at 0x%x in %s (below %s)" % (a, name, args.root))
    try:
        bound = stack_bound(funcs, root)
    except RecursionError as e:
        bound = None
        errors += 1
        print("audit: ERROR recursion below %s through %s: stack unbounded" % (args.root, e))

    # Panic sites: calls from outside the panic machinery into it.
    sites = []
    for s, f in funcs.items():
        if PANIC_NAME.match(f["name"]):
            continue
        for a, c in f["sites"]:
            if PANIC_NAME.match(funcs[c]["name"]):
                sites.append((a, s, c))
    chains = symbolize(args.elf, [a for a, _, _ in sites])
    unknown = 0
    for a, s, c in sorted(sites):
        chain = chains.get(a, [])
        text = " <- ".join(loc for _, loc in chain)
        is_known = any(k in text for k in known)
        in_step = s in below
        if not is_known:
            unknown += 1
        print("audit: %s panic site 0x%x%s: %s -> %s\n         %s" % (
            "known" if is_known else "UNKNOWN",
            a,
            " (reachable from %s)" % args.root if in_step else "",
            f_name_short(funcs[s]["name"]),
            funcs[c]["name"],
            text,
        ))
    if unknown:
        errors += 1
        print("audit: ERROR %d panic site(s) not in the known list" % unknown)

    in_step = sum(1 for _, s, _ in sites if s in below)
    print("audit.reachable_functions: %d" % len(below))
    print("audit.code_bytes: %d (functions reachable from %s)" % (code, args.root))
    print("audit.stack_bound_bytes: %s (static bound for %s, no interrupts)" % (
        bound if bound is not None else "unbounded", args.root))
    print("audit.panic_sites: %d in the program, %d reachable from %s, %d unknown" % (
        len(sites), in_step, args.root, unknown))
    print("audit.indirect_calls: %d, recursion: %s, allocator: %s" % (
        len(indirect), "no" if bound is not None else "YES", "no" if not allocs else "YES"))
    return 1 if errors else 0


def f_name_short(name):
    return re.sub(r"::h[0-9a-f]{16}$", "", name)


if __name__ == "__main__":
    sys.exit(main())
