// CHOLMOD (rbpart's supernodal settings; SIMPL=1: simplicial LDL') on the symmetric part of a dumped matrix,
// against KLU's refactorisation of the same matrix. g++ -O2 -I/usr/include/eigen3 chol.cpp -o chol -lcholmod -lklu
#include <suitesparse/cholmod.h>
#include <suitesparse/klu.h>
#include <Eigen/SparseCore>
#include "dumped_matrix.hpp"
#include <cstdio>
#include <vector>
#include <cstdlib>
using namespace std;
int main(int argc,char**argv){
  for(int a=1;a<argc;++a){
    DumpedMatrix d = read_dumped(argv[a]);
    const int n = d.n, nnz = d.nnz;
    vector<int>& p = d.p; vector<int>& i = d.i; vector<double>& x = d.x;
    Eigen::Map<const Eigen::SparseMatrix<double>> m(n,n,nnz,p.data(),i.data(),x.data());
    Eigen::SparseMatrix<double> S = 0.5*(Eigen::SparseMatrix<double>(m) + Eigen::SparseMatrix<double>(m.transpose()));
    S.makeCompressed();
    cholmod_common c; cholmod_start(&c);
    c.supernodal = getenv("SIMPL") ? CHOLMOD_SIMPLICIAL : CHOLMOD_SUPERNODAL; c.nmethods=1; c.method[0].ordering=CHOLMOD_AMD; c.postorder=1;
    c.nrelax[0]=16;c.nrelax[1]=64;c.nrelax[2]=128;c.zrelax[0]=0.8;c.zrelax[1]=0.3;c.zrelax[2]=0.1; c.print=0;
    cholmod_sparse A{}; A.nrow=A.ncol=n; A.nzmax=S.nonZeros(); A.p=S.outerIndexPtr(); A.i=S.innerIndexPtr(); A.x=S.valuePtr();
    A.stype=-1; A.itype=CHOLMOD_INT; A.xtype=CHOLMOD_REAL; A.dtype=CHOLMOD_DOUBLE; A.sorted=1; A.packed=1;
    cholmod_factor* L=cholmod_analyze(&A,&c);
    cholmod_factorize(&A,L,&c);
    const int R=10; double t0=now_ms(); for(int r=0;r<R;++r) cholmod_factorize(&A,L,&c); double tc=(now_ms()-t0)/R;
    int ok = c.status==CHOLMOD_OK && L->minor==L->n;
    Eigen::VectorXd bv=Eigen::VectorXd::Random(n); cholmod_dense B{}; B.nrow=B.d=B.nzmax=n; B.ncol=1; B.xtype=CHOLMOD_REAL; B.dtype=CHOLMOD_DOUBLE; B.x=bv.data();
    cholmod_dense* X=cholmod_solve(CHOLMOD_A,L,&B,&c);
    Eigen::Map<Eigen::VectorXd> xv((double*)X->x,n);
    Eigen::SparseMatrix<double> Sf = S.selfadjointView<Eigen::Lower>();
    printf("  solve residual %.2e |x| %.2e\n",(Sf*xv-bv).norm()/bv.norm(), xv.norm());
    klu_common k; klu_defaults(&k);
    klu_symbolic* Sy=klu_analyze(n,S.outerIndexPtr(),S.innerIndexPtr(),&k);
    klu_numeric* Nu=klu_factor(S.outerIndexPtr(),S.innerIndexPtr(),S.valuePtr(),Sy,&k);
    t0=now_ms(); for(int r=0;r<R;++r) klu_refactor(S.outerIndexPtr(),S.innerIndexPtr(),S.valuePtr(),Sy,Nu,&k); double tk=(now_ms()-t0)/R;
    printf("%s n=%d CHOLMOD %.3f ms (posdef %d, flops %.2e) KLU refactor (same matrix) %.3f ms\n",argv[a],n,tc,ok,c.fl,tk);
  }
}
