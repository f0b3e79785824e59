#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <algorithm>
#include <fstream>
#include <string>
#ifdef USE_DNNL
#include <dnnl.h>
#else
extern "C" void cblas_sgemm(int, int, int, int, int, int, float, const float*, int, const float*, int, float, float*, int);
#endif
struct S { long m,k,n; int ta,tb; };
int main(int argc, char** argv) {
  std::ifstream in(argv[1]); std::vector<S> v; S s;
  while (in >> s.m >> s.k >> s.n >> s.ta >> s.tb) v.push_back(s);
  std::vector<std::vector<float>> A,B,C;
  for (auto& x: v) { A.emplace_back(x.m*x.k, 0.5f); B.emplace_back(x.k*x.n, 0.25f); C.emplace_back(x.m*x.n); }
  auto run = [&](size_t i){ auto& x=v[i];
    long lda = x.ta ? x.m : x.k, ldb = x.tb ? x.k : x.n;
#ifdef USE_DNNL
    dnnl_sgemm(x.ta?'T':'N', x.tb?'T':'N', x.m, x.n, x.k, 1.f, A[i].data(), lda, B[i].data(), ldb, 0.f, C[i].data(), x.n);
#else
    cblas_sgemm(101, x.ta?112:111, x.tb?112:111, x.m, x.n, x.k, 1.f, A[i].data(), lda, B[i].data(), ldb, 0.f, C[i].data(), x.n);
#endif
  };
  double flops=0; for (auto& x: v) flops += 2.0*x.m*x.k*x.n;
  std::vector<double> t;
  for (int r=0;r<15;++r){ auto a=std::chrono::steady_clock::now(); for(size_t i=0;i<v.size();++i) run(i);
    t.push_back(std::chrono::duration<double,std::milli>(std::chrono::steady_clock::now()-a).count()); }
  std::sort(t.begin(),t.end());
  printf("%s: %zu gemms %.3f GFLOP median %.2f ms = %.1f GFLOP/s\n", argv[2], v.size(), flops*1e-9, t[7], flops*1e-6/t[7]);
  // per shape class
  if (argc>3) for (size_t i=0;i<v.size();++i){ auto a=std::chrono::steady_clock::now(); for(int r=0;r<20;++r) run(i);
    double ms=std::chrono::duration<double,std::milli>(std::chrono::steady_clock::now()-a).count()/20;
    printf("  %ld %ld %ld %d%d %.3f ms %.1f GF/s\n", v[i].m,v[i].k,v[i].n,v[i].ta,v[i].tb, ms, 2.0*v[i].m*v[i].k*v[i].n*1e-6/ms);}
}
