"""The in-house algorithms, implemented faithfully from the seed documents (weak spots included).

Importing this package registers them.  Where the seed's text has a weakness
that the implementation used to fix quietly, the algorithm is literal and the
fix is a named variant beside it:

=========================  ===  ===============================================
name                       dim  seed
=========================  ===  ===============================================
``naive-2d``               2    004 Cardiff lecture notes, naive O(n^3) hull
``monotone-chain``         2    004 Cardiff lecture notes, Andrew's monotone chain
``jarvis-march``           2    003 Jarvis march with collinear points (Unity)
``jarvis-march-sorted``    2    variant: collinear points in boundary order
``gift-wrap-3d``           3    000 Paul Nathan, 3D gift wrapping
``gift-wrap-3d-dedup``     3    variant: a re-found triangle is not added again
``henckel``                3    001 John Henckel, a direct convex hull
``henckel-normalised``     3    variant: the sort key divided by ``|P - B|``
``kenwright``              3    002 Ben Kenwright, sphere-projection hull
=========================  ===  ===============================================
"""

from . import gift_wrap, henckel, jarvis, kenwright, monotone_chain, naive2d  # noqa: F401
