#!/usr/bin/env python3
"""The fill of a Cholesky factor of softway's step matrix under METIS nested dissection.

    python bench/peers/fill.py DIR        # DIR written by `softway matrix SCENARIO --out DIR`

Reads DIR/A.mtx and DIR/matrix.json, orders the node graph (a node's two dofs together)
by METIS nested dissection (pymetis), counts the entries of the node-level Cholesky factor
by a symbolic factorization (elimination tree, column structures merged up the tree) and
expands them to dofs (each node entry a 2x2 block, the diagonal blocks lower-triangular),
beside softway's Cholesky (AMD on the dofs) from matrix.json. Needs numpy, scipy, pymetis.
Not part of CI.
"""
import json
import os
import sys

import numpy as np
import pymetis
import scipy.io
import scipy.sparse as sp


def node_graph(a):
    n = a.shape[0]
    s = (abs(a) + abs(a.T)).tocsr()
    p = sp.csr_matrix((np.ones(n), (np.arange(n), np.arange(n) // 2)), shape=(n, n // 2))
    g = (p.T @ s @ p).tocsr()
    g.setdiag(0)
    g.eliminate_zeros()
    return g


def cholesky_nnz(g, perm):
    """Entries of L (diagonal included) for the symmetric pattern `g` ordered by `perm`."""
    m = g.shape[0]
    gp = g[perm][:, perm].tocsc()
    ptr, idx = gp.indptr, gp.indices
    parent = -np.ones(m, dtype=np.int64)
    ancestor = -np.ones(m, dtype=np.int64)
    for j in range(m):
        for q in range(ptr[j], ptr[j + 1]):
            i = idx[q]
            while i != -1 and i < j:
                nxt = ancestor[i]
                ancestor[i] = j
                if nxt == -1:
                    parent[i] = j
                i = nxt
    children = [[] for _ in range(m)]
    for j in range(m):
        if parent[j] != -1:
            children[parent[j]].append(j)
    cols = [None] * m
    total = 0
    for j in range(m):
        s = {int(i) for i in idx[ptr[j]:ptr[j + 1]] if i > j}
        for c in children[j]:
            s |= cols[c]
            cols[c] = None
        s.discard(j)
        cols[j] = s
        total += len(s) + 1
    return total


def main():
    d = sys.argv[1]
    a = sp.csc_matrix(scipy.io.mmread(os.path.join(d, "A.mtx")))
    info = json.load(open(os.path.join(d, "matrix.json")))
    g = node_graph(a)
    m = g.shape[0]
    adj = [g.indices[g.indptr[i]:g.indptr[i + 1]].tolist() for i in range(m)]
    perm, iperm = pymetis.nested_dissection(adjacency=adj)
    # pymetis's two arrays: take the ordering with the smaller fill (the other is its inverse).
    nodes = min(cholesky_nnz(g, np.array(perm)), cholesky_nnz(g, np.array(iperm)))
    dofs = 4 * nodes - m  # off-diagonal blocks 4 entries, diagonal blocks 3
    print(f"{a.shape[0]} dofs ({m} nodes)")
    print(f"{'ordering':44} {'nnz(L)':>12}")
    for name, nnz in info["factor_nnz"]:
        if name.startswith("llt"):
            print(f"{'softway ' + name:44} {nnz:>12}")
    print(f"{'METIS nested dissection (node graph)':44} {dofs:>12}")


if __name__ == "__main__":
    main()
