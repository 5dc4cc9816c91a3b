// Eigen's SparseLU (COLAMD) on a dumped matrix: factorize and solve times, for comparison with lu.cpp.
// g++ -O3 -DNDEBUG -I/usr/include/eigen3 elu.cpp -o elu && ./elu /tmp/dump/m*.bin
#include <Eigen/SparseLU>
#include <Eigen/SparseCore>
#include "dumped_matrix.hpp"
#include <cstdio>
#include <vector>
using namespace std;
int main(int argc,char**argv){
  for(int a=1;a<argc;++a){
    DumpedMatrix d = read_dumped(argv[a]);
    const int n = d.n, nnz = d.nnz;
    vector<int>& p = d.p; vector<int>& i = d.i; vector<double>& x = d.x;
    Eigen::Map<const Eigen::SparseMatrix<double>> m(n,n,nnz,p.data(),i.data(),x.data());
    Eigen::SparseMatrix<double> A(m);
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
    lu.analyzePattern(A);
    lu.factorize(A);
    const int R=10; double t0=now_ms(); for(int r=0;r<R;++r) lu.factorize(A); double tf=(now_ms()-t0)/R;
    Eigen::VectorXd b=Eigen::VectorXd::Random(n); t0=now_ms(); Eigen::VectorXd xs; for(int r=0;r<R;++r) xs=lu.solve(b); double ts=(now_ms()-t0)/R;
    printf("%s n=%d eigen SparseLU factorize %.3f ms solve %.3f ms residual %.1e info %d\n",argv[a],n,tf,ts,(A*xs-b).norm()/b.norm(),(int)lu.info());
  }
}
