"""Lossless factorisation of a detail map into X diag(S) Y^T (paper §5).

SVD (§5.1): the fewest singular values whose float32 reconstruction rounds to the map exactly.
BMF (§5.2): binary X and Y; each term is the greedy maximal biclique of the entries equal to the
residual's maximum, scaled by that maximum, subtracted until the residual is zero.

Facade maps repeat whole rows and columns, so both work on the matrix of distinct rows and
columns, weighted by how often each repeats, and expand X and Y afterwards. For the SVD this is
exact algebra: with R (C) the 0/1 matrices selecting each row's (column's) distinct line and
W = R^T R the repeat counts, D = R U C^T and the SVD of W_r^1/2 U W_c^1/2 gives the SVD of D.
For the BMF, repeated rows have identical neighbourhoods, so the greedy biclique takes them
together and the weighted search finds the same bicliques.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import CityshadeError

METHODS = ("svd", "bmf")
MAX_TERMS = 4096  # S is one texture row on the GPU; far more terms means the map is not facade-like
# The GPU sums the terms in its own order; keeping the CPU's float32 error this far under 0.5
# makes the GPU's rounding land on the same integer.
SVD_TOLERANCE = 0.45


@dataclass(frozen=True)
class Factors:
    """map == rint(X diag(S) Y^T): X (rows, p), Y (cols, p), S (p,). X and Y are bool for BMF."""

    method: str
    x: np.ndarray
    s: np.ndarray
    y: np.ndarray

    @property
    def terms(self) -> int:
        return int(self.s.size)

    @property
    def shape(self) -> tuple[int, int]:
        return self.x.shape[0], self.y.shape[0]

    def reconstruct(self) -> np.ndarray:
        """The map as uint32, computed as the GPU does (float32 sums, then rounding)."""
        if self.terms == 0:
            return np.zeros(self.shape, np.uint32)
        x = self.x.astype(np.float32)
        product = (x * self.s.astype(np.float32)) @ self.y.astype(np.float32).T
        return np.rint(product).astype(np.uint32)

    def nbytes(self) -> int:
        """Bytes on the GPU: float32 X, S, Y for SVD; 32 bits of X and Y per R32UI texel for BMF."""
        rows, cols = self.shape
        if self.method == "svd":
            return 4 * self.terms * (rows + cols + 1)
        words = -(-self.terms // 32)
        return 4 * (words * (rows + cols) + self.terms)


class _Distinct:
    """The distinct rows and columns of a matrix, their repeat counts and the expansion maps."""

    def __init__(self, matrix: np.ndarray):
        rows, self.row_of = _unique_lines(matrix)
        cols, self.col_of = _unique_lines(matrix[rows].T)
        self.core = matrix[rows][:, cols].astype(np.int64)
        self.row_weight = np.bincount(self.row_of, minlength=len(rows))
        self.col_weight = np.bincount(self.col_of, minlength=len(cols))


def _unique_lines(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index of the first occurrence of each distinct row, and each row's distinct-row number."""
    contiguous = np.ascontiguousarray(matrix)
    keys = contiguous.view(np.dtype((np.void, contiguous.dtype.itemsize * contiguous.shape[1]))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    return first, inverse.ravel()


def factorize(matrix: np.ndarray, method: str, max_terms: int = MAX_TERMS, name: str = "map") -> Factors:
    """Exact factorisation of a non-negative integer matrix; raises CityshadeError if it needs
    more than max_terms terms."""
    if method not in METHODS:
        raise CityshadeError(f"unknown factorisation method {method!r}; use one of {', '.join(METHODS)}")
    if matrix.dtype.kind not in "ui" or (matrix.size and matrix.min() < 0):
        raise CityshadeError(f"{name}: only non-negative integer maps can be factorised")
    distinct = _Distinct(matrix)
    core_factors = (_svd if method == "svd" else _bmf)(distinct, max_terms, name)
    x, s, y = core_factors
    return Factors(method, x[distinct.row_of], s, y[distinct.col_of])


def _too_many(name: str, method: str, max_terms: int) -> CityshadeError:
    return CityshadeError(
        f"{name}: the {method.upper()} factorisation needs more than {max_terms} terms; the map is not made of "
        "rectangles of equal values (a photograph or noise?): use a coarser texel or fewer distinct values"
    )


def _svd(distinct: _Distinct, max_terms: int, name: str):
    core = distinct.core.astype(np.float64)
    wr, wc = np.sqrt(distinct.row_weight), np.sqrt(distinct.col_weight)
    left, sigma, right_t = np.linalg.svd(wr[:, None] * core * wc[None, :], full_matrices=False)
    x = (left / wr[:, None]).astype(np.float32)
    y = (right_t.T / wc[:, None]).astype(np.float32)
    s = sigma.astype(np.float32)
    target = distinct.core.astype(np.float32)
    partial = np.zeros_like(target)
    # Summed term by term in float32, in the order the GPU sums them.
    for p in range(0, min(len(s), max_terms) + 1):
        if p:
            partial += (x[:, p - 1] * s[p - 1])[:, None] * y[None, :, p - 1]
        if np.abs(partial - target).max(initial=0.0) <= SVD_TOLERANCE:
            return x[:, :p], s[:p], y[:, :p]
    raise _too_many(name, "svd", max_terms)


def _bmf(distinct: _Distinct, max_terms: int, name: str):
    residual = distinct.core.copy()
    xs, ys, ss = [], [], []
    while residual.any():
        if len(ss) == max_terms:
            raise _too_many(name, "bmf", max_terms)
        sigma = residual.max()
        rows, cols = greedy_biclique(residual == sigma, distinct.row_weight, distinct.col_weight)
        residual[np.ix_(rows, cols)] -= sigma
        xs.append(rows)
        ys.append(cols)
        ss.append(sigma)
    r, c = residual.shape
    x = np.array(xs, bool).T.reshape(r, len(ss))
    y = np.array(ys, bool).T.reshape(c, len(ss))
    return x, np.array(ss, np.float32), y


def greedy_biclique(edges: np.ndarray, row_weight: np.ndarray, col_weight: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The paper's greedy maximal complete bipartite subgraph of a 0/1 matrix (rows = V_x,
    columns = V_y), with weights counting repeated rows and columns. Returns boolean masks.

    Start from the row with the most (weighted) neighbours; repeatedly add the row with the most
    neighbours among the current columns and drop the columns it misses; return the largest
    |L_x| |L_y| seen. Rows adjacent to every current column are taken in one step, since each
    would be the next choice and none shrinks the column set."""
    edges_f = edges.astype(np.float64)
    counts = edges_f @ col_weight
    start = int(np.argmax(counts))
    in_x = np.zeros(edges.shape[0], bool)
    in_x[start] = True
    cols = edges[start].copy()
    x_weight = int(row_weight[start])
    best = (x_weight * counts[start], in_x.copy(), cols.copy())
    while True:
        col_total = float(col_weight[cols].sum())
        if col_total == 0:
            break
        counts = edges_f[:, cols] @ col_weight[cols]
        counts[in_x] = -1.0
        full = counts == col_total
        if full.any():
            in_x |= full
            x_weight += int(row_weight[full].sum())
        else:
            nxt = int(np.argmax(counts))
            if counts[nxt] <= 0:
                break
            in_x[nxt] = True
            x_weight += int(row_weight[nxt])
            cols &= edges[nxt]
            col_total = float(col_weight[cols].sum())
        size = x_weight * col_total
        if size > best[0]:
            best = (size, in_x.copy(), cols.copy())
    return best[1], best[2]
