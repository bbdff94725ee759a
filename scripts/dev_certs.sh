#!/bin/sh
# Writes a throw-away certificate authority and a server and a client
# certificate signed by it into DIR, for tests, the container smoke test and
# trying TLS locally (never for production: the CA key lies beside them):
#   ca.crt ca.key  server.crt server.key (localhost, 127.0.0.1 and $EXTRA_SANS)
#   client.crt client.key (for mutual TLS)
# usage: scripts/dev_certs.sh DIR     (EXTRA_SANS="DNS:gistream,IP:10.0.0.5")
set -eu
dir=${1:?usage: dev_certs.sh DIR}
mkdir -p "$dir"
cd "$dir"
ec="-newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes"
openssl req -x509 $ec -keyout ca.key -out ca.crt -days 7 -subj /CN=gistream-dev-ca 2>/dev/null
sans="DNS:localhost,IP:127.0.0.1${EXTRA_SANS:+,$EXTRA_SANS}"
for who in server client; do
  openssl req $ec -keyout $who.key -out $who.csr -subj /CN=gistream-$who 2>/dev/null
  if [ $who = server ]; then
    printf 'subjectAltName=%s\nextendedKeyUsage=serverAuth\n' "$sans" > $who.ext
  else
    printf 'extendedKeyUsage=clientAuth\n' > $who.ext
  fi
  openssl x509 -req -in $who.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out $who.crt \
    -days 7 -extfile $who.ext 2>/dev/null
  rm -f $who.csr $who.ext
done
rm -f ca.srl
chmod 600 ./*.key
