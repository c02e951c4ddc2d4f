"""The in-house algorithms, implemented faithfully from the seed documents (weak spots included).

Importing this package registers them:

========================  ===  ===============================================
name                      dim  seed
========================  ===  ===============================================
``naive-2d``              2    004 Cardiff lecture notes, naive O(n^3) hull
``monotone-chain``        2    004 Cardiff lecture notes, Andrew's monotone chain
``jarvis-march``          2    003 Jarvis march with collinear points (Unity)
``gift-wrap-3d``          3    000 Paul Nathan, 3D gift wrapping
``henckel``               3    001 John Henckel, a direct convex hull
``kenwright``             3    002 Ben Kenwright, sphere-projection hull
========================  ===  ===============================================
"""

from . import gift_wrap, henckel, jarvis, kenwright, monotone_chain, naive2d  # noqa: F401
