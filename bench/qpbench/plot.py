# SPDX-License-Identifier: MIT
"""matplotlib without a display (bench/install-deps.sh installs python3-matplotlib for /usr/bin/python3)."""

import sys


def pyplot(who):
    """matplotlib.pyplot on the Agg backend, or None (after saying so on stderr) when it is not installed."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        return plt
    except ImportError:
        print(f"{who}: matplotlib missing (bench/install-deps.sh installs python3-matplotlib): no plots",
              file=sys.stderr)
        return None


def save(plt, fig, path, dpi=None):
    fig.tight_layout()
    fig.savefig(path, dpi=dpi) if dpi else fig.savefig(path)
    plt.close(fig)
    return path
