//! WebAssembly binding of heartmesh-core (under construction).
