"""lpv-explorer: an interactive explorer of Light Propagation Volumes."""

__version__ = "0.1.0"
