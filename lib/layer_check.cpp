// The program each ffd_layer_check_<folder> links with one folder's whole archive and the
// folders below it (lib/CMakeLists.txt): it links only if the folder calls nothing above.
int main() { return 0; }
