"""The compiled (numba) filter loop behind :func:`xnavlab.mars.navigation.scenarios.run`.

One step of the filter per module (the inputs, the linear algebra, the time update, the
measurement updates, the fusion, the combined detector), sharing one numba cache keyed by
all their sources (:data:`xnavlab.mars.kernel.kernel_compile.SOURCES`).

=========================  ===============================================================
module                     what it models
=========================  ===============================================================
``kernels``                the compiled (numba) filter loop behind ``scenarios.run``, with the
                           combined detector inside it
``kernel_inputs``          the kernel's arguments in six named containers, with units
``kernel_compile``         how the kernel is compiled and cached: options, the cache's key
``kernel_linalg``          the small linear algebra: a 6 x 6 product, Cholesky, its solves
``kernel_propagation``     the time update: the forces, RK4, the transition matrix, Q
``kernel_measurements``    the three sensors' models and the local EKF updates
``kernel_fusion``          the master: the federated fusion, in two forms that agree
``kernel_watch``           the combined detector inside the compiled loop
``compile_notice``         the one-line notice before the kernel's first compile
=========================  ===============================================================

The modules are imported by name (``from xnavlab.mars.kernel import kernels``);
importing the subpackage imports none of them.
"""

__all__: list[str] = []
