// Eigen's SparseLU (COLAMD) on a dumped matrix: factorize and solve times, for comparison with lu.cpp.
// g++ -O3 -DNDEBUG -I/usr/include/eigen3 elu.cpp -o elu && ./elu /tmp/dump/m*.bin
#include <Eigen/SparseLU>
#include <Eigen/SparseCore>
#include <chrono>
#include <cstdio>
#include <vector>
using namespace std;
static double now(){return chrono::duration<double,milli>(chrono::steady_clock::now().time_since_epoch()).count();}
int main(int argc,char**argv){
  for(int a=1;a<argc;++a){
    FILE*f=fopen(argv[a],"rb"); int n,nnz; fread(&n,4,1,f);fread(&nnz,4,1,f);
    vector<int> p(n+1),i(nnz); vector<double> x(nnz); fread(p.data(),4,n+1,f);fread(i.data(),4,nnz,f);fread(x.data(),8,nnz,f);fclose(f);
    Eigen::Map<const Eigen::SparseMatrix<double>> m(n,n,nnz,p.data(),i.data(),x.data());
    Eigen::SparseMatrix<double> A(m);
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
    lu.analyzePattern(A);
    lu.factorize(A);
    const int R=10; double t0=now(); for(int r=0;r<R;++r) lu.factorize(A); double tf=(now()-t0)/R;
    Eigen::VectorXd b=Eigen::VectorXd::Random(n); t0=now(); Eigen::VectorXd xs; for(int r=0;r<R;++r) xs=lu.solve(b); double ts=(now()-t0)/R;
    printf("%s n=%d eigen SparseLU factorize %.3f ms solve %.3f ms residual %.1e info %d\n",argv[a],n,tf,ts,(A*xs-b).norm()/b.norm(),(int)lu.info());
  }
}
