"""camtol: precision disk-cam mechanisms: design, tolerance, inspection, manufacturing."""

__version__ = "0.1.0"
