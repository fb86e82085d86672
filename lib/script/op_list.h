// The registered ops, one line each (see op.h). The order is the schema's and the
// reference's order.
FFD_OP(lattice_op)
FFD_OP(move_op)
FFD_OP(drag_op)
FFD_OP(subdivide_op)
FFD_OP(rbf_op)
FFD_OP(idw_op)
FFD_OP(cage_op)
FFD_OP(remesh_op)
FFD_OP(save_op)
FFD_OP(bcm_op)
FFD_OP(transform_op)
