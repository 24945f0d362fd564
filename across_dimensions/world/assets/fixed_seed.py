"""A fixed seed for fTetWild, so one surface always bakes to the same tets.

fTetWild (pytetwild 0.2.3) draws some of its choices from ``std::random_device``,
the operating system's entropy: the same surface with the same settings bakes to
a different mesh on every run (tree.obj: 615, 714 and 697 vertices in three runs),
one thread or many, with address randomisation off or on. The wrapper library
imports that draw (``std::random_device::_M_getval``) from libstdc++ through its
global offset table, so the bake's child process points that one entry at a
fixed sequence before it tetrahedralizes. With it the same input gives the same
bytes, run after run (``tests/test_bake_assets.py`` bakes in fresh processes and
compares them).

Only the child process of a bake does this (:mod:`.tetwild`), never the game:
the table entry is the wrapper's own, read from its ELF relocations, and written
once. Where it cannot be done (not Linux on x86-64, another libstdc++ name, a
relocation kind this does not know), :func:`fix_random_device` returns False
and the bake runs as fTetWild made it; the bake's hash still names the result.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import mmap
import struct
import sys

#: The libstdc++ member that returns one draw of ``std::random_device``.
SYMBOL = b"_ZNSt13random_device9_M_getvalEv"
#: Relocation kinds that fill a table entry with a function's address (x86-64).
_SLOT_KINDS = (6, 7)  # R_X86_64_GLOB_DAT, R_X86_64_JUMP_SLOT
_SHT_RELA = 4
_RTLD_DI_LINKMAP = 2
_PROT_READ, _PROT_WRITE = 1, 2

_DRAW = ctypes.CFUNCTYPE(ctypes.c_uint, ctypes.c_void_p)
_kept: list = []  # the callback must outlive every call into the library


def _sequence(seed: int):
    """A fixed stream of 32-bit draws (a 64-bit LCG's high half; quality is not the point)."""
    state = seed

    def draw(_this) -> int:
        nonlocal state
        state = (state * 6364136223846793005 + 1442695040888963407) & 0xFFFFFFFFFFFFFFFF
        return state >> 32

    return draw


def slot_offsets(elf: bytes, symbol: bytes = SYMBOL) -> list[int]:
    """Offsets (from the library's load address) of the table entries that hold ``symbol``.

    Parameters
    ----------
    elf : bytes
        A 64-bit little-endian ELF shared object.

    Returns
    -------
    list of int
        Empty when ``symbol`` is not imported through a table entry.
    """
    if elf[:4] != b"\x7fELF" or elf[4] != 2 or elf[5] != 1:
        return []
    (shoff,) = struct.unpack_from("<Q", elf, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", elf, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", elf, shoff + i * shentsize) for i in range(shnum)]
    found = []
    for _name, kind, _flags, _addr, offset, size, link, _info, _align, entsize in sections:
        if kind != _SHT_RELA or not entsize:
            continue
        symtab = sections[link]
        strtab = sections[symtab[6]]
        for at in range(offset, offset + size, entsize):
            r_offset, r_info, _addend = struct.unpack_from("<QQq", elf, at)
            if r_info & 0xFFFFFFFF not in _SLOT_KINDS:
                continue
            (st_name,) = struct.unpack_from("<I", elf, symtab[4] + (r_info >> 32) * symtab[9])
            start = strtab[4] + st_name
            if elf[start : elf.index(b"\0", start)] == symbol:
                found.append(r_offset)
    return found


def fix_random_device(library_path: str, seed: int = 20210501) -> bool:
    """Point the loaded ``library_path``'s ``std::random_device`` draws at a fixed sequence.

    Parameters
    ----------
    library_path : str
        A shared object already loaded in this process (pytetwild's wrapper).
    seed : int
        Start of the sequence; part of what a bake is (see ``bake_cache.BAKE_SETTINGS``).

    Returns
    -------
    bool
        True when every table entry for the draw now points at the sequence.
    """
    if not sys.platform.startswith("linux") or struct.calcsize("P") != 8:
        return False
    try:
        with open(library_path, "rb") as f:
            offsets = slot_offsets(f.read())
        if not offsets:
            return False
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        handle = ctypes.CDLL(library_path)._handle  # already loaded: the same handle, no second copy
        link_map = ctypes.POINTER(ctypes.c_size_t)()
        if libc.dlinfo(ctypes.c_void_p(handle), _RTLD_DI_LINKMAP, ctypes.byref(link_map)) != 0:
            return False
        base = link_map[0]  # struct link_map starts with l_addr, the load address
        draw = _DRAW(_sequence(seed))
        _kept.append(draw)
        address = ctypes.cast(draw, ctypes.c_void_p).value
        page = mmap.PAGESIZE
        for offset in offsets:
            slot = base + offset
            start = slot - slot % page
            # Full RELRO leaves the table read-only once loaded: open its page for writing (and
            # leave it so: with lazy binding the loader still writes to it; the child ends soon).
            if libc.mprotect(ctypes.c_void_p(start), page, _PROT_READ | _PROT_WRITE) != 0:
                return False
            ctypes.c_void_p.from_address(slot).value = address
        return True
    except (OSError, ValueError, IndexError, struct.error, AttributeError):
        return False
