"""EXPRESS: exact symbolic equations of motion for rail vehicles with linkages.

Re-creates and extends the program of Tanifuji & Suzuki (2001): describe a vehicle
as rigid bodies, connection points, spring/damper elements and pinned joints, and get
its linear equations of motion ``M q'' + C q' + K q = P u + Pd u'`` as exact,
simplified symbolic matrices, plus the rail modules and analyses built on them.
"""

__version__ = "0.1.0"

from express.base.kernel_cache import configure_kernel_cache as _configure_kernel_cache

_configure_kernel_cache()  # before Numba is imported: a writable place for the compiled kernels
