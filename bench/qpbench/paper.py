# SPDX-License-Identifier: MIT
"""The paper's Tables 1 and 2: objects handled within 20 ms (higher is better), by quadtree depth 4..9."""

DEPTHS = [4, 5, 6, 7, 8, 9]
TABLES = {
    "i7-7500U (2 cores / 4 threads)": {
        "Seq.": [7970, 15200, 26300, 41600, 39500, 28600],
        "Static": [5430, 10390, 19600, 33900, 51600, 58900],
        "Dyn.": [5460, 10340, 19300, 33800, 51000, 46700],
        "Guided": [5420, 10280, 19300, 33700, 51600, 47800],
    },
    "Ryzen 7 1700 (8 cores / 16 threads)": {
        "Seq.": [8970, 17100, 30700, 49200, 54000, 33600],
        "Static": [4790, 9460, 17600, 30800, 42500, 39400],
        "Dyn.": [4780, 9190, 17200, 30500, 41800, 37300],
        "Guided": [4780, 9210, 17200, 30600, 40600, 37500],
    },
}
