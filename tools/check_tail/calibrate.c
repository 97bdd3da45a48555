/* Calibration of check's heavy-tail rule (check_tail.h; docs/statistics.md "When check cannot
 * judge"): 40 synthetic run sets per distribution, K runs x S series each, through
 * check_tail_measure; prints how many were flagged at c = 0, 1, 2 standard deviations
 * (the rule uses c = 1). Build and run from the repository root:
 *   make build/librestir.a && cc -O2 -std=c99 -D_DEFAULT_SOURCE -Iinclude tools/check_tail/calibrate.c \
 *       build/librestir.a -lm -o build/check_tail_calibrate && build/check_tail_calibrate */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "restir/check_tail.h"
static double nrm(void){double u=drand48(),v=drand48();return sqrt(-2*log(u+1e-300))*cos(2*M_PI*v);}
static double par(double a){return pow(1-drand48(),-1/a)-1;}
static double gen(int kind){
  int i; double s=0;
  switch(kind){
  case 0: return nrm();
  case 1: return -log(1-drand48());
  case 2: return exp(nrm());
  case 3: return par(3);
  case 4: return par(1.5);
  case 5: return par(1.2);
  case 6: for(i=0;i<16;++i) s+=par(1.5); return s/16;
  case 7: for(i=0;i<64;++i) s+=-log(1-drand48()); return s/64;
  case 8: return nrm()+(drand48()<0.05?100:0);
  case 9: for(i=0;i<64;++i) s+=-log(1-drand48())*(drand48()<0.1?10:1); return s/64; /* firefly-ish finite var */
  }
  return 0;
}
static const char*names[]={"normal","exp","lognormal1","pareto3","pareto1.5","pareto1.2","mean16 pareto1.5","mean64 exp","normal+5%x100","mean64 mix"};
int main(void){
  int kind,Ks[]={8,16,32},nbs[]={27,192,768},ki,ni,rep;
  srand48(1);
  int kinds[]={0,1,2,4,5,6,7,9}; int kk; for(kk=0;kk<8;++kk) if((kind=kinds[kk]),1) for(ki=0;ki<3;++ki) for(ni=0;ni<3;++ni){
    int K=Ks[ki],nb=nbs[ni]; double lo=1e9,hi=0,sum=0; int heavy=0,h1=0,h2=0;
    for(rep=0;rep<40;++rep){
      double *x=malloc(sizeof(double)*K*nb); long k,j; check_tail t;
      for(k=0;k<K;++k) for(j=0;j<nb;++j) x[k*nb+j]=gen(kind);
      check_tail_measure(&t,x,K,nb,nb,NULL,0);
      if(t.tail_index<lo)lo=t.tail_index; if(t.tail_index>hi)hi=t.tail_index; sum+=t.tail_index; heavy+=t.tail_index<2; h1+=t.tail_index*(1+1/sqrt(t.tail_count))<2; h2+=t.tail_index*(1+2/sqrt(t.tail_count))<2;
      free(x);
    }
    printf("%-18s K=%2d series=%3d alpha mean %.2f range %.2f..%.2f heavy c0 %2d c1 %2d c2 %2d /40\n",names[kind],K,nb,sum/40,lo,hi,heavy,h1,h2);
  }
  return 0;
}
