"""Reports: terminal tables, JSON, CSV curves, plots, exports and HTML.

Submodules are imported on demand so that ``import camtol`` stays light (matplotlib and
ezdxf load only when a figure or a DXF file is asked for).
"""
