"""Bit packing of binary factors (paper §6): 32 consecutive terms of a row in one 32-bit word,
term k in bit k % 32 of word k // 32, so a row of X with p terms becomes ceil(p / 32) R32UI texels."""

from __future__ import annotations

import numpy as np


def pack_bits(bits: np.ndarray) -> np.ndarray:
    """(rows, p) bool -> (rows, ceil(p / 32)) uint32."""
    rows, terms = bits.shape
    words = -(-terms // 32)
    padded = np.zeros((rows, words * 32), bool)
    padded[:, :terms] = bits
    packed = np.packbits(padded, axis=1, bitorder="little")
    return packed.view("<u4").astype(np.uint32).reshape(rows, words)


def unpack_bits(words: np.ndarray, terms: int) -> np.ndarray:
    """(rows, ceil(p / 32)) uint32 -> (rows, p) bool."""
    as_bytes = np.ascontiguousarray(words.astype("<u4")).view(np.uint8)
    return np.unpackbits(as_bytes, axis=1, bitorder="little")[:, :terms].astype(bool)
