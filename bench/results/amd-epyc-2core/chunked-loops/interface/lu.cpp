// KLU (refactor with the first LU's pivots, full factor, refactor without scaling) against UMFPACK's
// numeric factorisation on matrices dumped by dump.patch; flop counts from both libraries.
// g++ -O2 lu.cpp -o lu -lklu -lumfpack && ./lu /tmp/dump/m*.bin
#include <suitesparse/klu.h>
#include <suitesparse/umfpack.h>
#include "dumped_matrix.hpp"
#include <cstdio>
#include <vector>
#include <string>
#include <cmath>
using namespace std;
int main(int argc,char**argv){
  for(int a=1;a<argc;++a){
    DumpedMatrix d = read_dumped(argv[a]);
    const int n = d.n, nnz = d.nnz;
    vector<int>& p = d.p; vector<int>& i = d.i; vector<double>& x = d.x;
    // KLU
    klu_common c; klu_defaults(&c);
    klu_symbolic*S=klu_analyze(n,p.data(),i.data(),&c);
    klu_numeric*N=klu_factor(p.data(),i.data(),x.data(),S,&c);
    double t0=now_ms(); int R=10;
    for(int r=0;r<R;++r) klu_refactor(p.data(),i.data(),x.data(),S,N,&c);
    double klu_re=(now_ms()-t0)/R;
    t0=now_ms(); for(int r=0;r<R;++r){klu_numeric*M=klu_factor(p.data(),i.data(),x.data(),S,&c); klu_free_numeric(&M,&c);} double klu_f=(now_ms()-t0)/R;
    klu_flops(S,N,&c); double kflops=c.flops; int lnz=N->lnz, unz=N->unz;
    klu_common c2; klu_defaults(&c2); c2.scale=0; klu_numeric*N2=klu_factor(p.data(),i.data(),x.data(),S,&c2);
    t0=now_ms(); for(int r=0;r<R;++r) klu_refactor(p.data(),i.data(),x.data(),S,N2,&c2); double klu_ns=(now_ms()-t0)/R;
    // UMFPACK
    double ctl[UMFPACK_CONTROL], info[UMFPACK_INFO]; umfpack_di_defaults(ctl);
    void*Sym; umfpack_di_symbolic(n,n,p.data(),i.data(),x.data(),&Sym,ctl,info);
    void*Num; t0=now_ms(); for(int r=0;r<R;++r){umfpack_di_numeric(p.data(),i.data(),x.data(),Sym,&Num,ctl,info); if(r<R-1) umfpack_di_free_numeric(&Num);} double umf=(now_ms()-t0)/R;
    double uflops=info[UMFPACK_FLOPS]; 
    printf("%-28s n=%5d nnz=%7d | klu refactor %.3f ms factor %.3f ms noscale-refac %.3f flops %.2e lnz+unz %d | umf numeric %.3f ms flops %.2e\n",argv[a],n,nnz,klu_re,klu_f,klu_ns,kflops,lnz+unz,umf,uflops);
    klu_free_numeric(&N,&c); klu_free_numeric(&N2,&c2); klu_free_symbolic(&S,&c); umfpack_di_free_numeric(&Num); umfpack_di_free_symbolic(&Sym);
  }
}
